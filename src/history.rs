//! Where a photon has been: how many reflections it made, on which mirrors (the
//! first and the last), and the path class that follows from the mirrors' stages
//! (front = primary, rear = secondary).
//!
//! Data flow: `scene` tags mirror objects with a [`MirrorStage`] and a shell; the
//! photon loop (`trace`) updates a [`History`] at every reflection and hands it to
//! the sensor record; `sensor` sums flux per class, shell and path; `output`
//! writes per-class images, photon lists and the summary.

use serde::{Deserialize, Serialize};

/// Which mirror of a two-reflection (Wolter-type) telescope an object is: an
/// object's `stage` in the scene file, set by the LLNL assembly for its mirrors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MirrorStage {
    /// The primary, met first by light from the source (paraboloid, front cone).
    Front,
    /// The secondary (hyperboloid, rear cone).
    Rear,
}

/// The path class of a recorded photon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum PathClass {
    /// No reflection: straight from the source.
    Direct = 0,
    /// Exactly two reflections, a front mirror then a rear mirror: the focus.
    FrontRear = 1,
    /// One reflection, on a front mirror.
    FrontOnly = 2,
    /// One reflection, on a rear mirror.
    RearOnly = 3,
    /// Anything else: three or more reflections, rear before front, two fronts,
    /// or mirrors without a stage.
    Other = 4,
}

impl PathClass {
    pub const ALL: [PathClass; 5] = [
        PathClass::Direct,
        PathClass::FrontRear,
        PathClass::FrontOnly,
        PathClass::RearOnly,
        PathClass::Other,
    ];

    /// The name used in file names and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            PathClass::Direct => "direct",
            PathClass::FrontRear => "front_rear",
            PathClass::FrontOnly => "front_only",
            PathClass::RearOnly => "rear_only",
            PathClass::Other => "other",
        }
    }

    pub fn from_index(i: u8) -> PathClass {
        PathClass::ALL[i.min(4) as usize]
    }
}

/// No mirror (in `first_mirror` / `last_mirror`).
pub const NO_MIRROR: u32 = u32::MAX;

/// One photon's reflections so far.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
pub struct History {
    pub reflections: u16,
    /// Object index of the first and the last mirror ([`NO_MIRROR`] if none).
    pub first_mirror: u32,
    pub last_mirror: u32,
    first_stage: Option<MirrorStage>,
    last_stage: Option<MirrorStage>,
}

impl Default for History {
    fn default() -> History {
        History {
            reflections: 0,
            first_mirror: NO_MIRROR,
            last_mirror: NO_MIRROR,
            first_stage: None,
            last_stage: None,
        }
    }
}

impl History {
    /// A reflection on object `object` of stage `stage`.
    #[inline]
    pub fn reflect(&mut self, object: usize, stage: Option<MirrorStage>) {
        if self.reflections == 0 {
            self.first_mirror = object as u32;
            self.first_stage = stage;
        }
        self.last_mirror = object as u32;
        self.last_stage = stage;
        self.reflections = self.reflections.saturating_add(1);
    }

    pub fn class(&self) -> PathClass {
        use MirrorStage::{Front, Rear};
        match (self.reflections, self.first_stage, self.last_stage) {
            (0, _, _) => PathClass::Direct,
            (1, Some(Front), _) => PathClass::FrontOnly,
            (1, Some(Rear), _) => PathClass::RearOnly,
            (2, Some(Front), Some(Rear)) => PathClass::FrontRear,
            _ => PathClass::Other,
        }
    }
}
