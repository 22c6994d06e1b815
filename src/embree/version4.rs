//! Embree 4: `rtcIntersect1(scene, rayhit, args)`, the context travels inside
//! RTCIntersectArguments.
use super::{sys, INVALID_ID};

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
/// `scene` must be committed; `ctx` (a traxer `QueryContext`'s, see
/// `callbacks`) and `rh` valid for the call.
#[inline]
pub unsafe fn intersect1(scene: sys::RTCScene, ctx: *mut Context, rh: &mut sys::RTCRayHit) {
    // Rust version of the inline `rtcInitIntersectArguments`.
    let mut args = sys::RTCIntersectArguments {
        flags: sys::RTC_RAY_QUERY_FLAG_INCOHERENT,
        feature_mask: sys::RTC_FEATURE_FLAG_ALL,
        context: ctx,
        ..Default::default()
    };
    // SAFETY: forwarded from the caller; `args` lives for the call.
    unsafe { sys::rtcIntersect1(scene, rh, &mut args) }
}
