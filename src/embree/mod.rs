//! The only `unsafe` code in traxer: a thin, safe wrapper over Intel Embree's C API.
//!
//! Data flow: `scene::build` hands triangle meshes (world-space f32 vertices) and
//! analytic shapes (any type implementing [`UserGeometry`], intersected in f64 by
//! Rust) to a [`SceneBuilder`]; [`SceneBuilder::commit`] turns it into a read-only
//! [`CommittedScene`] that every tracing thread shares; `trace` asks it for the
//! nearest hit of one f64 ray at a time ([`CommittedScene::intersect`]).
//!
//! Embree 3 and 4 differ in a handful of calls (see ARCHITECTURE.md); `build.rs`
//! sets `cfg(embree3)` or `cfg(embree4)` from the headers it found, and the two small
//! `version` modules below hold every difference.
//!
//! Rules kept here:
//! * one [`Device`] with an error callback; the first error is stored and checked
//!   after each commit, never per ray;
//! * geometries are released right after they are attached (the scene owns them);
//! * scenes use `RTC_SCENE_FLAG_ROBUST`: without it grazing rays aimed at triangle
//!   seams leak through;
//! * user-geometry callbacks never unwind into C (an `extern "C"` function that
//!   panics aborts) and read the shape through a pointer to data the scene owns.
#![allow(unsafe_code)]

#[allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code,
    clippy::all
)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/embree_bindings.rs"));
}

use std::cell::Cell;
use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;
use std::sync::{Arc, Mutex};

/// `RTC_INVALID_GEOMETRY_ID` (a cast macro bindgen does not translate).
pub const INVALID_ID: u32 = u32::MAX;

/// Major version of the Embree library this build links (3 or 4).
#[cfg(embree3)]
pub const EMBREE_MAJOR: u32 = 3;
/// Major version of the Embree library this build links (3 or 4).
#[cfg(embree4)]
pub const EMBREE_MAJOR: u32 = 4;

/// Errors reported by Embree.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    #[error("Embree could not create a device: {0}")]
    NoDevice(String),
    #[error("Embree reported an error ({code}): {message}")]
    Reported { code: u32, message: String },
    #[error("too many objects for Embree geometry ids: {0}")]
    TooManyGeometries(usize),
}

/// An analytic shape that Embree treats as user geometry: Embree only sees its
/// bounding box; the exact intersection is computed by Rust in f64.
pub trait UserGeometry: Send + Sync + 'static {
    /// World-space axis-aligned bounds (lower, upper), slightly padded by the caller.
    fn bounds(&self) -> ([f32; 3], [f32; 3]);
    /// Distance `t` (in units of `dir`) to the nearest hit with `t < t_max`.
    /// `starts_on_surface` is true when the ray leaves a point of this same
    /// surface (after a reflection): the root at t ≈ 0 must then be ignored, but a
    /// genuine second hit on the same (concave) surface must not.
    fn intersect(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64>;
}

/// Embree's bound on ray origin and direction components (`FLT_LARGE` in its
/// sources); `Ray::valid()` rejects anything larger.
const EMBREE_FLT_LARGE: f32 = 1.844e18;

/// One ray query, in f64. Embree's triangle test sees the f32 rounding of it;
/// user geometry sees it exactly. A query Embree cannot represent misses.
#[derive(Clone, Copy, Debug)]
pub struct Query {
    pub origin: [f64; 3],
    /// Direction; need not be normalised (t is in its units).
    pub dir: [f64; 3],
    /// Only hits with t < t_max count (use `f64::INFINITY` for none).
    pub t_max: f64,
    /// Geometry id of the user-geometry surface the ray starts on, or [`INVALID_ID`].
    pub start_geometry: u32,
}

/// The nearest hit Embree found.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub geometry: u32,
    pub primitive: u32,
    /// Distance along the query direction: exact f64 for user geometry, Embree's
    /// f32 value for triangles (refine it in f64 if it matters).
    pub t: f64,
    /// Barycentric coordinates of a triangle hit (0 for user geometry).
    pub u: f32,
    pub v: f32,
}

/// Facts about the linked Embree library, for `traxer info` and provenance.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DeviceInfo {
    /// e.g. "3.13.5"
    pub version: String,
    pub major: u32,
    /// Native packet widths the library was compiled for: 4 = SSE, 8 = AVX/AVX2,
    /// 16 = AVX-512. They show which instruction sets the library can use.
    pub native_packets: Vec<u32>,
    /// "internal", "TBB" or "PPL".
    pub tasking_system: String,
    pub robust_mode: bool,
}

/// The first error Embree reported since the last check.
type ErrorSlot = Mutex<Option<(u32, String)>>;

struct DeviceInner {
    raw: sys::RTCDevice,
    // Boxed so the pointer given to Embree's error callback stays valid.
    errors: Box<ErrorSlot>,
}

// SAFETY: an RTCDevice is a reference-counted, thread-safe handle (Embree's API
// documents device functions as thread-safe); the error slot is a Mutex.
unsafe impl Send for DeviceInner {}
// SAFETY: as above.
unsafe impl Sync for DeviceInner {}

impl Drop for DeviceInner {
    fn drop(&mut self) {
        // SAFETY: `raw` was created by rtcNewDevice and is released exactly once; the
        // scenes hold an Arc to this, so none outlives it.
        unsafe { sys::rtcReleaseDevice(self.raw) };
    }
}

/// An Embree device: create one per process and build scenes from it.
#[derive(Clone)]
pub struct Device {
    inner: Arc<DeviceInner>,
}

unsafe extern "C" fn error_callback(
    user: *mut c_void,
    code: sys::RTCError,
    message: *const c_char,
) {
    if user.is_null() {
        return;
    }
    // SAFETY: `user` is the Box<ErrorSlot> owned by the DeviceInner that registered
    // this callback; it lives as long as the device.
    let slot = unsafe { &*(user as *const ErrorSlot) };
    let text = if message.is_null() {
        String::from("(no message)")
    } else {
        // SAFETY: Embree passes a NUL-terminated string valid for this call.
        unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned()
    };
    if let Ok(mut first) = slot.lock() {
        if first.is_none() {
            // RTCError's Rust type differs between bindgen/Embree versions.
            #[allow(clippy::unnecessary_cast)]
            let code = code as u32;
            *first = Some((code, text));
        }
    }
}

impl Device {
    /// Creates a device with Embree's default configuration.
    pub fn new() -> Result<Device, EmbreeError> {
        let config = CString::new("verbose=0").expect("static string has no NUL");
        // SAFETY: a valid NUL-terminated config string; a NULL result is handled.
        let raw = unsafe { sys::rtcNewDevice(config.as_ptr()) };
        if raw.is_null() {
            // SAFETY: rtcGetDeviceError accepts NULL and returns the thread's last error.
            let code = unsafe { sys::rtcGetDeviceError(std::ptr::null_mut()) };
            return Err(EmbreeError::NoDevice(format!("error code {}", code as u32)));
        }
        let errors: Box<ErrorSlot> = Box::new(Mutex::new(None));
        // SAFETY: the user pointer is the boxed slot, which lives as long as `raw`
        // (both are dropped together in DeviceInner).
        unsafe {
            sys::rtcSetDeviceErrorFunction(
                raw,
                Some(error_callback),
                &*errors as *const ErrorSlot as *mut c_void,
            )
        };
        Ok(Device {
            inner: Arc::new(DeviceInner { raw, errors }),
        })
    }

    /// Returns (and clears) the first error Embree reported since the last call.
    pub fn check(&self) -> Result<(), EmbreeError> {
        let mut slot = self.inner.errors.lock().unwrap_or_else(|p| p.into_inner());
        match slot.take() {
            Some((code, message)) => Err(EmbreeError::Reported { code, message }),
            None => Ok(()),
        }
    }

    fn property(&self, p: sys::RTCDeviceProperty) -> isize {
        // SAFETY: valid device and a property constant from the headers.
        let v = unsafe { sys::rtcGetDeviceProperty(self.inner.raw, p) };
        #[allow(clippy::unnecessary_cast)] // ssize_t maps to isize or i64
        let v = v as isize;
        v
    }

    /// Version, native packet widths and tasking system of the linked library.
    pub fn info(&self) -> DeviceInfo {
        let v = self.property(sys::RTC_DEVICE_PROPERTY_VERSION);
        let mut native_packets = Vec::new();
        for (w, p) in [
            (4, sys::RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED),
            (8, sys::RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
            (16, sys::RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED),
        ] {
            if self.property(p) != 0 {
                native_packets.push(w);
            }
        }
        let tasking_system = match self.property(sys::RTC_DEVICE_PROPERTY_TASKING_SYSTEM) {
            0 => "internal",
            1 => "TBB",
            2 => "PPL",
            _ => "unknown",
        }
        .to_string();
        // The property exists in both versions; it is 0 only in exotic builds.
        let _ = self.check();
        DeviceInfo {
            version: format!("{}.{}.{}", v / 10000, (v / 100) % 100, v % 100),
            major: EMBREE_MAJOR,
            native_packets,
            tasking_system,
            robust_mode: true,
        }
    }

    /// Starts a new scene. `U` is the type of the analytic shapes it may hold.
    pub fn scene<U: UserGeometry>(&self) -> SceneBuilder<U> {
        // SAFETY: valid device; the scene handle is owned by the returned builder.
        let raw = unsafe { sys::rtcNewScene(self.inner.raw) };
        // SAFETY: valid scene handle; flag and quality constants from the headers.
        unsafe {
            sys::rtcSetSceneFlags(raw, sys::RTC_SCENE_FLAG_ROBUST);
            sys::rtcSetSceneBuildQuality(raw, sys::RTC_BUILD_QUALITY_HIGH);
        }
        SceneBuilder {
            device: self.clone(),
            raw,
            user: Vec::new(),
        }
    }
}

/// A scene being assembled. Geometry ids are chosen by the caller (object indices).
pub struct SceneBuilder<U: UserGeometry> {
    device: Device,
    raw: sys::RTCScene,
    // Boxed so that the pointers handed to Embree stay valid when the Vec grows.
    user: Vec<Box<U>>,
}

impl<U: UserGeometry> Drop for SceneBuilder<U> {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: the builder owns one reference to the scene.
            unsafe { sys::rtcReleaseScene(self.raw) };
        }
    }
}

impl<U: UserGeometry> SceneBuilder<U> {
    /// Adds a triangle mesh under geometry id `id`.
    /// `vertices` are world-space positions, `triangles` index triples into them
    /// (the caller has checked that every index is in range).
    pub fn add_triangles(
        &mut self,
        id: u32,
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
    ) -> Result<(), EmbreeError> {
        let dev = self.device.inner.raw;
        // SAFETY: valid device; the geometry handle is released below after attaching.
        let geom = unsafe { sys::rtcNewGeometry(dev, sys::RTC_GEOMETRY_TYPE_TRIANGLE) };
        if geom.is_null() {
            self.device.check()?;
            return Err(EmbreeError::NoDevice("rtcNewGeometry returned NULL".into()));
        }
        // SAFETY: rtcSetNewGeometryBuffer allocates a buffer of exactly
        // count × stride bytes (plus the padding Embree needs for 16-byte loads) and
        // returns a pointer to it, or NULL on failure (checked). We write exactly
        // `count` elements of the declared layout.
        unsafe {
            let vb = sys::rtcSetNewGeometryBuffer(
                geom,
                sys::RTC_BUFFER_TYPE_VERTEX,
                0,
                sys::RTC_FORMAT_FLOAT3,
                12,
                vertices.len(),
            ) as *mut [f32; 3];
            let ib = sys::rtcSetNewGeometryBuffer(
                geom,
                sys::RTC_BUFFER_TYPE_INDEX,
                0,
                sys::RTC_FORMAT_UINT3,
                12,
                triangles.len(),
            ) as *mut [u32; 3];
            if vb.is_null() || ib.is_null() {
                sys::rtcReleaseGeometry(geom);
                self.device.check()?;
                return Err(EmbreeError::NoDevice(
                    "cannot allocate geometry buffers".into(),
                ));
            }
            std::ptr::copy_nonoverlapping(vertices.as_ptr(), vb, vertices.len());
            std::ptr::copy_nonoverlapping(triangles.as_ptr(), ib, triangles.len());
            sys::rtcCommitGeometry(geom);
            sys::rtcAttachGeometryByID(self.raw, geom, id);
            sys::rtcReleaseGeometry(geom);
        }
        self.device.check()
    }

    /// Adds an analytic shape (one primitive) under geometry id `id`; Embree will
    /// call back into `shape.intersect` for rays that reach its bounding box.
    pub fn add_user(&mut self, id: u32, shape: U) -> Result<(), EmbreeError> {
        let boxed = Box::new(shape);
        let ptr = &*boxed as *const U as *mut c_void;
        self.user.push(boxed);
        let dev = self.device.inner.raw;
        // SAFETY: valid device and scene. The user pointer refers to a Box owned by
        // this builder and then by the CommittedScene, so it outlives every query;
        // the callbacks only read through it.
        unsafe {
            let geom = sys::rtcNewGeometry(dev, sys::RTC_GEOMETRY_TYPE_USER);
            if geom.is_null() {
                self.device.check()?;
                return Err(EmbreeError::NoDevice("rtcNewGeometry returned NULL".into()));
            }
            sys::rtcSetGeometryUserPrimitiveCount(geom, 1);
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
        })
    }
}

/// A built scene: read-only, shared by all tracing threads.
pub struct CommittedScene<U: UserGeometry> {
    raw: sys::RTCScene,
    _device: Device,
    // Owns the shapes the user-geometry callbacks point to.
    _user: Vec<Box<U>>,
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

/// Our ray-query context: Embree's context first, so that the pointer Embree hands
/// to callbacks can be cast back to this (the documented way to pass per-ray data).
#[repr(C)]
struct QueryContext {
    rtc: version::Context,
    origin: [f64; 3],
    dir: [f64; 3],
    start_geometry: u32,
    // Written by the intersect callback: exact t of the last accepted user hit.
    user_geometry: Cell<u32>,
    user_t: Cell<f64>,
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
        unsafe { version::intersect1(self.raw, &ctx, &mut rh) };
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

unsafe extern "C" fn bounds_callback<U: UserGeometry>(
    args: *const sys::RTCBoundsFunctionArguments,
) {
    // SAFETY: Embree passes valid arguments; geometryUserPtr is the Box<U> set in
    // add_user, alive as long as the scene; bounds_o points to writable RTCBounds.
    unsafe {
        let args = &*args;
        let shape = &*(args.geometryUserPtr as *const U);
        let (lo, hi) = shape.bounds();
        let b = &mut *args.bounds_o;
        b.lower_x = lo[0];
        b.lower_y = lo[1];
        b.lower_z = lo[2];
        b.upper_x = hi[0];
        b.upper_y = hi[1];
        b.upper_z = hi[2];
    }
}

unsafe extern "C" fn intersect_callback<U: UserGeometry>(
    args: *const sys::RTCIntersectFunctionNArguments,
) {
    // SAFETY: Embree passes valid arguments. traxer only issues single-ray queries
    // (rtcIntersect1), for which N == 1 and the RTCRayHitN block has exactly the
    // layout of RTCRayHit (structure-of-arrays with one lane). The context is the
    // first field of our #[repr(C)] QueryContext, so the cast is valid; it is only
    // read, and written through Cells. geometryUserPtr is the Box<U> of add_user.
    unsafe {
        let args = &*args;
        if args.N != 1 || *args.valid == 0 {
            return;
        }
        let ctx = &*(args.context as *const QueryContext);
        let shape = &*(args.geometryUserPtr as *const U);
        let rh = &mut *(args.rayhit as *mut sys::RTCRayHit);
        let tfar = rh.ray.tfar;
        let starts_here = ctx.start_geometry == args.geomID;
        if let Some(t) = shape.intersect(ctx.origin, ctx.dir, tfar as f64, starts_here) {
            let t32 = t as f32;
            if t32 < tfar && t > 0.0 {
                rh.ray.tfar = t32;
                rh.hit.geomID = args.geomID;
                rh.hit.primID = args.primID;
                rh.hit.u = 0.0;
                rh.hit.v = 0.0;
                rh.hit.Ng_x = 0.0;
                rh.hit.Ng_y = 0.0;
                rh.hit.Ng_z = 1.0;
                ctx.user_geometry.set(args.geomID);
                ctx.user_t.set(t);
            }
        }
    }
}

unsafe extern "C" fn occluded_callback<U: UserGeometry>(
    args: *const sys::RTCOccludedFunctionNArguments,
) {
    // SAFETY: as in intersect_callback; for occlusion Embree expects tfar = -inf on
    // a hit. (traxer does not issue occlusion queries today; this keeps the
    // geometry complete.)
    unsafe {
        let args = &*args;
        if args.N != 1 || *args.valid == 0 {
            return;
        }
        let ctx = &*(args.context as *const QueryContext);
        let shape = &*(args.geometryUserPtr as *const U);
        let ray = &mut *(args.ray as *mut sys::RTCRay);
        let starts_here = ctx.start_geometry == args.geomID;
        if shape
            .intersect(ctx.origin, ctx.dir, ray.tfar as f64, starts_here)
            .is_some()
        {
            ray.tfar = f32::NEG_INFINITY;
        }
    }
}

/// Raw throughput probe for benchmarks: `rtcIntersect1` on f32 rays with nothing
/// of traxer's per-hit work around it.
impl<U: UserGeometry> CommittedScene<U> {
    /// Intersects each ray and returns how many hit something.
    pub fn intersect_raw(&self, rays: &[([f32; 3], [f32; 3])]) -> usize {
        let mut hits = 0;
        for (o, d) in rays {
            let q = Query {
                origin: [o[0] as f64, o[1] as f64, o[2] as f64],
                dir: [d[0] as f64, d[1] as f64, d[2] as f64],
                t_max: f64::INFINITY,
                start_geometry: INVALID_ID,
            };
            if self.intersect(&q).is_some() {
                hits += 1;
            }
        }
        hits
    }
}

#[cfg(embree3)]
mod version {
    //! Embree 3: `rtcIntersect1(scene, context, rayhit)` with an RTCIntersectContext.
    use super::{sys, QueryContext, INVALID_ID};

    pub type Context = sys::RTCIntersectContext;

    /// Rust version of the inline `rtcInitIntersectContext`.
    pub fn new_context() -> Context {
        let mut c = Context {
            flags: sys::RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
            filter: None,
            ..Default::default()
        };
        for id in c.instID.iter_mut() {
            *id = INVALID_ID;
        }
        c
    }

    /// # Safety
    /// `scene` must be committed; `ctx` and `rh` valid for the call.
    #[inline]
    pub unsafe fn intersect1(scene: sys::RTCScene, ctx: &QueryContext, rh: &mut sys::RTCRayHit) {
        // SAFETY: forwarded from the caller. Embree takes a mutable context pointer
        // but does not write the base context during traversal.
        unsafe { sys::rtcIntersect1(scene, &ctx.rtc as *const Context as *mut Context, rh) }
    }
}

#[cfg(embree4)]
mod version {
    //! Embree 4: `rtcIntersect1(scene, rayhit, args)`, the context travels inside
    //! RTCIntersectArguments.
    use super::{sys, QueryContext, INVALID_ID};

    pub type Context = sys::RTCRayQueryContext;

    /// Rust version of the inline `rtcInitRayQueryContext`.
    pub fn new_context() -> Context {
        let mut c = Context::default();
        for id in c.instID.iter_mut() {
            *id = INVALID_ID;
        }
        init_inst_prim_id(&mut c);
        c
    }

    #[cfg(embree_inst_prim_id)]
    fn init_inst_prim_id(c: &mut Context) {
        for id in c.instPrimID.iter_mut() {
            *id = INVALID_ID;
        }
    }
    #[cfg(not(embree_inst_prim_id))]
    fn init_inst_prim_id(_: &mut Context) {}

    /// # Safety
    /// `scene` must be committed; `ctx` and `rh` valid for the call.
    #[inline]
    pub unsafe fn intersect1(scene: sys::RTCScene, ctx: &QueryContext, rh: &mut sys::RTCRayHit) {
        // Rust version of the inline `rtcInitIntersectArguments`.
        let mut args = sys::RTCIntersectArguments {
            flags: sys::RTC_RAY_QUERY_FLAG_INCOHERENT,
            feature_mask: sys::RTC_FEATURE_FLAG_ALL,
            context: &ctx.rtc as *const Context as *mut Context,
            ..Default::default()
        };
        // SAFETY: forwarded from the caller; `args` lives for the call.
        unsafe { sys::rtcIntersect1(scene, rh, &mut args) }
    }
}
