//! Embree scenes: assembled from triangle meshes and user geometry, committed into
//! a read-only [`CommittedScene`] that answers one f64 ray query at a time.

use super::callbacks::{bounds_callback, intersect_callback, occluded_callback, QueryContext};
use super::device::Device;
use super::{sys, version, EmbreeError, Hit, Query, UserGeometry, EMBREE_FLT_LARGE, INVALID_ID};
use std::cell::Cell;
use std::ffi::c_void;
use std::sync::Arc;

/// A scene being assembled. Geometry ids are chosen by the caller (object indices).
pub struct SceneBuilder<U: UserGeometry> {
    device: Device,
    raw: sys::RTCScene,
    // Boxed so that the pointers handed to Embree stay valid when the Vec grows.
    user: Vec<Box<U>>,
    // Index buffers Embree reads in place (shared, not copied).
    shared: Vec<Arc<Vec<[u32; 3]>>>,
}

impl<U: UserGeometry> Drop for SceneBuilder<U> {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: the builder owns one reference to the scene.
            unsafe { sys::rtcReleaseScene(self.raw) };
        }
    }
}

impl Device {
    /// Starts a new scene. `U` is the type of the analytic shapes it may hold.
    /// (Here, not in `device`: the device knows nothing of scenes.)
    pub fn scene<U: UserGeometry>(&self) -> SceneBuilder<U> {
        SceneBuilder::new(self.clone())
    }
}

impl<U: UserGeometry> SceneBuilder<U> {
    /// A new, empty scene of `device` (robust, high-quality BVH).
    pub(super) fn new(device: Device) -> SceneBuilder<U> {
        // SAFETY: valid device; the scene handle is owned by the returned builder.
        let raw = unsafe { sys::rtcNewScene(device.raw()) };
        // SAFETY: valid scene handle; flag and quality constants from the headers.
        unsafe {
            sys::rtcSetSceneFlags(raw, sys::RTC_SCENE_FLAG_ROBUST);
            sys::rtcSetSceneBuildQuality(raw, sys::RTC_BUILD_QUALITY_HIGH);
        }
        SceneBuilder {
            device,
            raw,
            user: Vec::new(),
            shared: Vec::new(),
        }
    }

    /// Adds a triangle mesh under geometry id `id`.
    /// `vertices` are world-space positions (written straight into Embree's
    /// buffer, no copy of the mesh in between), `triangles` index triples
    /// into them (the caller has checked that every index is in range). Embree
    /// reads the triangles in place, so that a 2-million-triangle mesh does not
    /// hold its 25 MB of indices twice; the scene keeps them alive.
    pub fn add_triangles(
        &mut self,
        id: u32,
        vertices: impl ExactSizeIterator<Item = [f32; 3]>,
        triangles: Arc<Vec<[u32; 3]>>,
    ) -> Result<(), EmbreeError> {
        let dev = self.device.raw();
        let count = vertices.len();
        // SAFETY: valid device; the geometry handle is released below after attaching.
        let geom = unsafe { sys::rtcNewGeometry(dev, sys::RTC_GEOMETRY_TYPE_TRIANGLE) };
        if geom.is_null() {
            self.device.check()?;
            return Err(EmbreeError::NoDevice("rtcNewGeometry returned NULL".into()));
        }
        // SAFETY: rtcSetNewGeometryBuffer allocates a buffer of exactly
        // count × stride bytes (plus the padding Embree needs for 16-byte loads of
        // vertices) and returns a pointer to it, or NULL on failure (checked). We
        // write exactly `count` elements of the declared layout. The shared index
        // buffer is 4-byte aligned with a 12-byte stride as Embree requires (only
        // vertex buffers need padding past the last element), and its Arc is kept
        // in the builder and then the committed scene, so it outlives every use.
        unsafe {
            let vb = sys::rtcSetNewGeometryBuffer(
                geom,
                sys::RTC_BUFFER_TYPE_VERTEX,
                0,
                sys::RTC_FORMAT_FLOAT3,
                12,
                count,
            ) as *mut [f32; 3];
            if vb.is_null() {
                sys::rtcReleaseGeometry(geom);
                self.device.check()?;
                return Err(EmbreeError::NoDevice(
                    "cannot allocate geometry buffers".into(),
                ));
            }
            // Never past `count`, and every element written (an iterator that
            // reports more than it yields leaves zeros, not uninitialised memory).
            let mut vertices = vertices.take(count);
            for k in 0..count {
                vb.add(k).write(vertices.next().unwrap_or_default());
            }
            sys::rtcSetSharedGeometryBuffer(
                geom,
                sys::RTC_BUFFER_TYPE_INDEX,
                0,
                sys::RTC_FORMAT_UINT3,
                triangles.as_ptr() as *const c_void,
                0,
                12,
                triangles.len(),
            );
            sys::rtcCommitGeometry(geom);
            sys::rtcAttachGeometryByID(self.raw, geom, id);
            sys::rtcReleaseGeometry(geom);
        }
        self.shared.push(triangles);
        self.device.check()
    }

    /// Adds an analytic shape (its primitives) under geometry id `id`; Embree
    /// will call back into `shape.intersect` for rays that reach a primitive's
    /// bounding box.
    pub fn add_user(&mut self, id: u32, shape: U) -> Result<(), EmbreeError> {
        let shape_primitives = shape.primitive_count();
        let boxed = Box::new(shape);
        let ptr = &*boxed as *const U as *mut c_void;
        self.user.push(boxed);
        let dev = self.device.raw();
        // SAFETY: valid device and scene. The user pointer refers to a Box owned by
        // this builder and then by the CommittedScene, so it outlives every query;
        // the callbacks only read through it.
        unsafe {
            let geom = sys::rtcNewGeometry(dev, sys::RTC_GEOMETRY_TYPE_USER);
            if geom.is_null() {
                self.device.check()?;
                return Err(EmbreeError::NoDevice("rtcNewGeometry returned NULL".into()));
            }
            sys::rtcSetGeometryUserPrimitiveCount(geom, shape_primitives);
            sys::rtcSetGeometryUserData(geom, ptr);
            sys::rtcSetGeometryBoundsFunction(
                geom,
                Some(bounds_callback::<U>),
                std::ptr::null_mut(),
            );
            sys::rtcSetGeometryIntersectFunction(geom, Some(intersect_callback::<U>));
            sys::rtcSetGeometryOccludedFunction(geom, Some(occluded_callback::<U>));
            sys::rtcCommitGeometry(geom);
            sys::rtcAttachGeometryByID(self.raw, geom, id);
            sys::rtcReleaseGeometry(geom);
        }
        self.device.check()
    }

    /// Builds the BVH. Errors reported by Embree during building surface here.
    pub fn commit(mut self) -> Result<CommittedScene<U>, EmbreeError> {
        // SAFETY: valid scene; after commit it is only read.
        unsafe { sys::rtcCommitScene(self.raw) };
        self.device.check()?;
        let raw = std::mem::replace(&mut self.raw, std::ptr::null_mut());
        Ok(CommittedScene {
            raw,
            _device: self.device.clone(),
            _user: std::mem::take(&mut self.user),
            _shared: std::mem::take(&mut self.shared),
        })
    }
}

/// A built scene: read-only, shared by all tracing threads.
pub struct CommittedScene<U: UserGeometry> {
    raw: sys::RTCScene,
    _device: Device,
    // Owns the shapes the user-geometry callbacks point to.
    _user: Vec<Box<U>>,
    // Owns the index buffers Embree reads in place.
    _shared: Vec<Arc<Vec<[u32; 3]>>>,
}

// SAFETY: after rtcCommitScene, Embree allows concurrent rtcIntersect1 calls on a
// scene from any number of threads; the user shapes are Send + Sync and only read.
unsafe impl<U: UserGeometry> Send for CommittedScene<U> {}
// SAFETY: as above.
unsafe impl<U: UserGeometry> Sync for CommittedScene<U> {}

impl<U: UserGeometry> Drop for CommittedScene<U> {
    fn drop(&mut self) {
        // SAFETY: this value owns one reference to the scene.
        unsafe { sys::rtcReleaseScene(self.raw) };
    }
}

impl<U: UserGeometry> CommittedScene<U> {
    /// Nearest hit of `q`, or `None` if the ray leaves the scene.
    #[inline]
    pub fn intersect(&self, q: &Query) -> Option<Hit> {
        let ctx = QueryContext {
            rtc: version::new_context(),
            origin: q.origin,
            dir: q.dir,
            start_geometry: q.start_geometry,
            user_geometry: Cell::new(INVALID_ID),
            user_t: Cell::new(0.0),
        };
        let mut rh = sys::RTCRayHit {
            ray: sys::RTCRay {
                org_x: q.origin[0] as f32,
                org_y: q.origin[1] as f32,
                org_z: q.origin[2] as f32,
                tnear: 0.0,
                dir_x: q.dir[0] as f32,
                dir_y: q.dir[1] as f32,
                dir_z: q.dir[2] as f32,
                time: 0.0,
                tfar: if q.t_max.is_finite() {
                    q.t_max as f32
                } else {
                    f32::INFINITY
                },
                mask: u32::MAX,
                id: 0,
                flags: 0,
            },
            ..Default::default()
        };
        // A ray Embree cannot represent (NaN, or coordinates beyond its FLT_LARGE)
        // makes a debug-asserting Embree build abort the whole process: it misses
        // instead. Scenes keep everything within geometry::WORLD_LIMIT_MM, so only
        // a numerical accident can get here.
        let r = &rh.ray;
        let valid = [r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z]
            .iter()
            .all(|v| v.abs() <= EMBREE_FLT_LARGE)
            && !r.tfar.is_nan();
        if !valid {
            return None;
        }
        rh.hit.geomID = INVALID_ID;
        rh.hit.primID = INVALID_ID;
        for id in rh.hit.instID.iter_mut() {
            *id = INVALID_ID;
        }
        // SAFETY: the scene is committed; `ctx` and `rh` live on this stack frame
        // for the whole call; callbacks only touch `ctx` through Cells.
        unsafe { version::intersect1(self.raw, ctx.as_context(), &mut rh) };
        if rh.hit.geomID == INVALID_ID {
            return None;
        }
        let t = if rh.hit.geomID == ctx.user_geometry.get() {
            ctx.user_t.get()
        } else {
            rh.ray.tfar as f64
        };
        Some(Hit {
            geometry: rh.hit.geomID,
            primitive: rh.hit.primID,
            t,
            u: rh.hit.u,
            v: rh.hit.v,
        })
    }
}

/// Raw throughput probe for benchmarks: `rtcIntersect1` on recorded queries with
/// nothing of traxer's per-hit work around it. The queries are the ones the run
/// issued, f64 origin and start surface included: a ray leaving an analytic mirror
/// must be told so, or (from its f32-rounded origin) it may meet that mirror again
/// a micrometre on and end there, which is far cheaper than the real query.
impl<U: UserGeometry> CommittedScene<U> {
    /// Intersects each query and returns how many hit something.
    pub fn intersect_raw(&self, queries: &[Query]) -> usize {
        queries
            .iter()
            .filter(|q| self.intersect(q).is_some())
            .count()
    }
}
