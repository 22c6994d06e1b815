//! The Embree device: created once, with an error callback whose first error is
//! kept and checked after each commit; scenes are started from it.

use super::{sys, EmbreeError, EMBREE_MAJOR};
use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;
use std::sync::{Arc, Mutex};

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

    /// The raw handle, for the scenes built from this device.
    pub(super) fn raw(&self) -> sys::RTCDevice {
        self.inner.raw
    }
}
