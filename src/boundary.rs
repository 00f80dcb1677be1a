//! The C boundary: panics are caught here, pointers and arrays are checked here.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};

use fmi_sys::fmi2::{fmi2Component, fmi2Status};

use crate::instance::Instance;
use crate::logging::Status;
use crate::state::Call;

/// Runs `f` on the instance behind `c` after the state-machine check for `call`.
/// NULL or foreign instances give fmi2Error; a panic gives fmi2Error, is logged, and puts the
/// instance into the Error state. Nothing unwinds into the host.
///
/// # Safety
/// `c` must be NULL or a pointer returned by `fmi2Instantiate` and not yet freed.
pub(crate) unsafe fn with_instance(
    c: fmi2Component,
    call: Call,
    f: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded from this function's contract.
        let Some(instance) = (unsafe { Instance::from_component(c) }) else {
            return Status::Error;
        };
        if !instance.begin_call(call) {
            return Status::Error;
        }
        f(instance)
    }));
    match outcome {
        Ok(status) => status as fmi2Status,
        Err(payload) => {
            let message = panic_message(payload.as_ref());
            let _ = catch_unwind(AssertUnwindSafe(|| {
                // SAFETY: as above; the instance memory is intact after an unwind.
                if let Some(instance) = unsafe { Instance::from_component(c) } {
                    instance.fail_internally(call, &message);
                }
            }));
            Status::Error as fmi2Status
        }
    }
}

/// Runs `f`, turning a panic into `fallback`.
pub(crate) fn guard<R>(fallback: R, f: impl FnOnce() -> R) -> R {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(fallback)
}

fn panic_message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

/// A C array as a slice: `n == 0` gives an empty slice whatever `ptr` is; NULL with `n > 0`
/// gives `None`.
///
/// # Safety
/// A non-NULL `ptr` must point to `n` valid elements for the lifetime `'a`.
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, n: usize) -> Option<&'a [T]> {
    match (n, ptr.is_null()) {
        (0, _) => Some(&[]),
        (_, true) => None,
        // SAFETY: non-NULL and, by contract, `n` valid elements.
        (_, false) => Some(unsafe { std::slice::from_raw_parts(ptr, n) }),
    }
}

/// A mutable C array as a slice, with the rules of [`slice`].
///
/// # Safety
/// A non-NULL `ptr` must point to `n` valid, exclusively borrowed elements for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize) -> Option<&'a mut [T]> {
    match (n, ptr.is_null()) {
        (0, _) => Some(&mut []),
        (_, true) => None,
        // SAFETY: non-NULL and, by contract, `n` valid elements.
        (_, false) => Some(unsafe { std::slice::from_raw_parts_mut(ptr, n) }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guard_turns_a_panic_into_the_fallback() {
        let status = guard(Status::Error, || -> Status { panic!("boom") });
        assert_eq!(status, Status::Error);
        assert_eq!(guard(Status::Error, || Status::Ok), Status::Ok);
    }

    #[test]
    fn null_instance_is_an_error_not_a_crash() {
        // SAFETY: NULL is allowed by the contract.
        let status = unsafe { with_instance(std::ptr::null_mut(), Call::DoStep, |_| Status::Ok) };
        assert_eq!(status, Status::Error as fmi2Status);
    }

    #[test]
    fn arrays_null_only_when_empty() {
        // SAFETY: NULL pointers with the given lengths.
        unsafe {
            assert_eq!(slice::<u32>(std::ptr::null(), 0), Some(&[][..]));
            assert_eq!(slice::<u32>(std::ptr::null(), 3), None);
            let v = [1u32, 2];
            assert_eq!(slice(v.as_ptr(), 2), Some(&v[..]));
        }
    }
}
