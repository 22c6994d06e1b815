//! The user-geometry callbacks Embree calls for analytic shapes: bounds,
//! intersect and occluded. They never unwind into C and only read the shape
//! through the pointer to data the scene owns.

use super::{sys, version, UserGeometry};
use std::cell::Cell;

/// Our ray-query context: Embree's context first, so that the pointer Embree hands
/// to callbacks can be cast back to this (the documented way to pass per-ray data).
#[repr(C)]
pub(super) struct QueryContext {
    pub(super) rtc: version::Context,
    pub(super) origin: [f64; 3],
    pub(super) dir: [f64; 3],
    pub(super) start_geometry: u32,
    // Written by the intersect callback: exact t of the last accepted user hit.
    pub(super) user_geometry: Cell<u32>,
    pub(super) user_t: Cell<f64>,
}

impl QueryContext {
    /// The pointer Embree takes as its context: to the whole of this value
    /// (Embree's context is its first field), so that the callbacks may read
    /// the rest through it.
    pub(super) fn as_context(&self) -> *mut version::Context {
        (self as *const QueryContext)
            .cast::<version::Context>()
            .cast_mut()
    }
}

pub(super) unsafe extern "C" fn bounds_callback<U: UserGeometry>(
    args: *const sys::RTCBoundsFunctionArguments,
) {
    // SAFETY: Embree passes valid arguments; geometryUserPtr is the Box<U> set in
    // add_user, alive as long as the scene; bounds_o points to writable RTCBounds.
    unsafe {
        let args = &*args;
        let shape = &*(args.geometryUserPtr as *const U);
        let (lo, hi) = shape.bounds(args.primID);
        let b = &mut *args.bounds_o;
        b.lower_x = lo[0];
        b.lower_y = lo[1];
        b.lower_z = lo[2];
        b.upper_x = hi[0];
        b.upper_y = hi[1];
        b.upper_z = hi[2];
    }
}

pub(super) unsafe extern "C" fn intersect_callback<U: UserGeometry>(
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
        if let Some(t) = shape.intersect(args.primID, ctx.origin, ctx.dir, tfar as f64, starts_here)
        {
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

pub(super) unsafe extern "C" fn occluded_callback<U: UserGeometry>(
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
            .intersect(
                args.primID,
                ctx.origin,
                ctx.dir,
                ray.tfar as f64,
                starts_here,
            )
            .is_some()
        {
            ray.tfar = f32::NEG_INFINITY;
        }
    }
}
