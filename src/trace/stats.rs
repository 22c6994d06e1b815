//! What happened to the photons of a run. Counters only add, so merging chunk
//! statistics is exact and order-independent.

/// Photon fates and interaction counts.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Statistics {
    pub photons_emitted: u64,
    /// Recorded by any sensor.
    pub reached_sensor: u64,
    /// Stopped by an absorber.
    pub absorbed: u64,
    /// Hit the non-reflecting side of a mirror.
    pub absorbed_mirror_back: u64,
    /// Reflected on an interpolated normal into the facet it hit (mesh artefact).
    pub reflected_into_surface: u64,
    /// Tilted below the mirror surface by the figure error (absorbed).
    pub scattered_below_surface: u64,
    /// Hit a sensor object outside its active area (absorbed, not recorded).
    pub sensor_outside_area: u64,
    /// Reached a sensor with an energy outside its energy bins.
    pub sensor_outside_energy_range: u64,
    /// Left the scene.
    pub escaped: u64,
    /// Still bouncing after max_interactions.
    pub max_interactions_reached: u64,
    /// Ray queries sent to Embree.
    pub embree_queries: u64,
    /// Interactions per object, indexed like the scene's objects.
    pub hits_per_object: Vec<u64>,
    /// Photons recorded per sensor, indexed like the scene's sensors.
    pub recorded_per_sensor: Vec<u64>,
    /// Photons stopped by each absorber after at least one reflection: what a
    /// detector's aperture, a strongback or a shell's edge took from the focused
    /// beam (the sensor figure names them). Indexed like the scene's objects;
    /// empty in checkpoints written before it existed.
    #[serde(default)]
    pub stopped_after_reflection: Vec<u64>,
    /// Recorded photons whose weight, or weight at a mass or campaign pair,
    /// could not be tallied: NaN, infinite, negative or above
    /// [`crate::trace::LARGEST_WEIGHT`]. A run with any is refused
    /// (`run::job`): the exact sums would count them as 0 or saturate.
    pub unusable_weights: u64,
}

impl Statistics {
    pub fn new(objects: usize, sensors: usize) -> Statistics {
        Statistics {
            hits_per_object: vec![0; objects],
            recorded_per_sensor: vec![0; sensors],
            stopped_after_reflection: vec![0; objects],
            ..Default::default()
        }
    }

    pub fn add(&mut self, o: &Statistics) {
        self.photons_emitted += o.photons_emitted;
        self.reached_sensor += o.reached_sensor;
        self.absorbed += o.absorbed;
        self.absorbed_mirror_back += o.absorbed_mirror_back;
        self.reflected_into_surface += o.reflected_into_surface;
        self.scattered_below_surface += o.scattered_below_surface;
        self.sensor_outside_area += o.sensor_outside_area;
        self.sensor_outside_energy_range += o.sensor_outside_energy_range;
        self.escaped += o.escaped;
        self.max_interactions_reached += o.max_interactions_reached;
        self.embree_queries += o.embree_queries;
        self.unusable_weights += o.unusable_weights;
        for (a, b) in self.hits_per_object.iter_mut().zip(&o.hits_per_object) {
            *a += b;
        }
        let stopped = &mut self.stopped_after_reflection;
        if stopped.len() < o.stopped_after_reflection.len() {
            stopped.resize(o.stopped_after_reflection.len(), 0);
        }
        for (a, b) in stopped.iter_mut().zip(&o.stopped_after_reflection) {
            *a += b;
        }
        for (a, b) in self
            .recorded_per_sensor
            .iter_mut()
            .zip(&o.recorded_per_sensor)
        {
            *a += b;
        }
    }

    /// Refuses a run some of whose recorded photons carried a weight the
    /// exact sums cannot hold (they would count as 0 or saturate the sum):
    /// its images would be plausible and wrong (`run::job` writes nothing).
    pub fn weights_tallied(&self) -> Result<(), String> {
        match self.unusable_weights {
            0 => Ok(()),
            n => Err(format!(
                "{n} of the {} recorded photons carried a weight that is not a number from 0 to {:e} (NaN, infinite or negative: a table, map or setting of the scene gives one): their images would be wrong, so nothing was written",
                self.reached_sensor,
                crate::trace::LARGEST_WEIGHT
            )),
        }
    }

    /// Every emitted photon ends in exactly one fate.
    pub fn fates(&self) -> u64 {
        self.reached_sensor
            + self.absorbed
            + self.absorbed_mirror_back
            + self.reflected_into_surface
            + self.scattered_below_surface
            + self.sensor_outside_area
            + self.sensor_outside_energy_range
            + self.escaped
            + self.max_interactions_reached
    }
}
