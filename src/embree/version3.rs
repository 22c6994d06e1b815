//! Embree 3: `rtcIntersect1(scene, context, rayhit)` with an RTCIntersectContext.
use super::{sys, INVALID_ID};

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
/// `scene` must be committed; `ctx` (a traxer `QueryContext`'s, see
/// `callbacks`) and `rh` valid for the call.
#[inline]
pub unsafe fn intersect1(scene: sys::RTCScene, ctx: *mut Context, rh: &mut sys::RTCRayHit) {
    // SAFETY: forwarded from the caller. Embree takes a mutable context pointer
    // but does not write the base context during traversal.
    unsafe { sys::rtcIntersect1(scene, ctx, rh) }
}
