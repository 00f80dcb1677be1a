//! The C boundary: panics are caught here, pointers and arrays are checked here.
//!
//! Panic output: Rust's default panic hook prints the message and a backtrace note on stderr
//! before `catch_unwind` sees the panic. [`install_panic_hook`] (called by fmi2Instantiate,
//! once per process) replaces it with a hook that, while an FMI call of this library runs on
//! the thread, only records the message and its location for the instance's logger (the
//! call returns fmi2Error and logs it); any other panic goes to the hook that was installed
//! before, so it prints as usual. The hook is per copy of the standard library: the FMU as a
//! shared library (its own copy) leaves the host's panic hook alone; linked as an rlib into a
//! Rust program it shares the program's hook, chained as said. A hook the host installs later
//! replaces this one: FMU panics then print again but are still caught.

use std::any::Any;
use std::cell::{Cell, RefCell};
use std::ffi::{CStr, c_char, c_void};
use std::panic::{AssertUnwindSafe, PanicHookInfo, catch_unwind};
use std::sync::Once;

use fmi_sys::fmi2::{fmi2Component, fmi2Status};

use crate::call_sequence::FmiCall;
use crate::instance::{Instance, Instantiation};
use crate::logging::{Logger, Status};
use crate::variables::LogCategory;

/// Runs `f` on the instance behind `c` after the state-machine check for `call` (of either
/// standard: their status codes agree). NULL or foreign instances give an error; a panic gives fmi2Error, is logged, and puts the
/// instance into the Error state. Nothing unwinds into the host.
///
/// # Safety
/// `c` must be NULL or a pointer returned by an instantiation function and not yet freed.
pub(crate) unsafe fn with_instance(
    c: fmi2Component,
    call: impl FmiCall,
    f: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    let outcome = catch_quietly(|| {
        // SAFETY: forwarded from this function's contract.
        let Some(instance) = (unsafe { Instance::from_component(c) }) else {
            return Status::Error;
        };
        if !instance.begin_call(call) {
            return Status::Error;
        }
        f(instance)
    });
    match outcome {
        Ok(status) => status as fmi2Status,
        Err(message) => {
            let _ = catch_quietly(|| {
                // SAFETY: as above; the instance memory is intact after an unwind.
                if let Some(instance) = unsafe { Instance::from_component(c) } {
                    instance.fail_internally(call, &message);
                }
            });
            Status::Error as fmi2Status
        }
    }
}

/// A C string argument as `CStr`, `None` for NULL.
///
/// # Safety
/// A non-NULL `s` must be NUL-terminated and live for `'a`.
pub(crate) unsafe fn c_str<'a>(s: *const c_char) -> Option<&'a CStr> {
    // SAFETY: forwarded from the contract.
    (!s.is_null()).then(|| unsafe { CStr::from_ptr(s) })
}

/// The end of either standard's instantiation: the new instance as the host's pointer, or
/// NULL with the reason logged.
pub(crate) fn instantiate(logger: Logger, with: Instantiation) -> *mut c_void {
    match Instance::new(logger, with) {
        Ok(instance) => Box::into_raw(instance) as *mut c_void,
        Err((logger, e)) => {
            logger.log(Status::Error, LogCategory::StatusError, &e.0);
            std::ptr::null_mut()
        }
    }
}

/// Either standard's FreeInstance: the instance behind `c` marked freed and released; NULL
/// and foreign pointers are left alone.
///
/// # Safety
/// `c` must be NULL or a pointer from an instantiation function; not used afterwards.
pub(crate) unsafe fn free_instance(c: *mut c_void) {
    guard((), || {
        // SAFETY: NULL or a live instance by contract.
        if let Some(instance) = unsafe { Instance::from_component(c) } {
            instance.mark_freed();
            // SAFETY: allocated by Box::into_raw in `instantiate`; freed once, by contract.
            drop(unsafe { Box::from_raw(instance as *mut Instance) });
        }
    })
}

/// Either standard's SetDebugLogging: `categories` as `n` names (none: every category).
///
/// # Safety
/// `c` a live instance or NULL; `categories` NULL or `n` C strings.
pub(crate) unsafe fn set_debug_logging(
    c: *mut c_void,
    call: impl FmiCall,
    on: bool,
    n: usize,
    categories: *const *const c_char,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, call, |inst| {
            let Some(names) = slice(categories, n) else {
                return inst.null_array("categories", n);
            };
            let names: Option<Vec<&CStr>> = names.iter().map(|s| c_str(*s)).collect();
            match names {
                Some(names) => inst.set_debug_logging(on, &names),
                None => inst.null_array("a category name", 1),
            }
        })
    }
}

/// Runs `f`, turning a panic into `fallback`.
pub(crate) fn guard<R>(fallback: R, f: impl FnOnce() -> R) -> R {
    catch_quietly(f).unwrap_or(fallback)
}

thread_local! {
    /// How many FMI calls of this library are running on this thread (nested: a logger
    /// callback may call back into the FMU).
    static CALL_DEPTH: Cell<u32> = const { Cell::new(0) };
    /// Where the last panic inside an FMI call happened, for its message.
    static PANIC_LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Installs the panic hook described in the module documentation, once per process.
pub(crate) fn install_panic_hook() {
    static INSTALL: Once = Once::new();
    // set_hook panics on a panicking thread (fmi2Instantiate called from a destructor while
    // unwinding): install at the next fmi2Instantiate instead.
    if std::thread::panicking() {
        return;
    }
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info: &PanicHookInfo<'_>| {
            if CALL_DEPTH.with(Cell::get) > 0 {
                let location = info
                    .location()
                    .map(|l| format!("{}:{}", l.file(), l.line()));
                PANIC_LOCATION.with(|p| *p.borrow_mut() = location);
            } else {
                previous(info);
            }
        }));
    });
}

/// Runs `f` as an FMI call: a panic comes back as its message (with where it happened), and
/// the hook does not print it.
fn catch_quietly<R>(f: impl FnOnce() -> R) -> Result<R, String> {
    CALL_DEPTH.with(|d| d.set(d.get() + 1));
    let outcome = catch_unwind(AssertUnwindSafe(f));
    CALL_DEPTH.with(|d| d.set(d.get() - 1));
    outcome.map_err(|payload| {
        let message = panic_message(payload.as_ref());
        match PANIC_LOCATION.with(|p| p.borrow_mut().take()) {
            Some(at) => format!("{message} at {at}"),
            None => message,
        }
    })
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

/// A mutable C array as a slice, with the rules of [`slice()`].
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

/// A C array argument as a slice: `*const T` read as `&[T]` ([`slice()`]), `*mut T` written as
/// `&mut [T]` ([`slice_mut()`]).
pub(crate) trait CArray {
    type Slice<'a>
    where
        Self: 'a;

    /// The `n` elements, with the rules of [`slice()`].
    ///
    /// # Safety
    /// As [`slice()`] for `*const T`, [`slice_mut()`] for `*mut T`.
    unsafe fn to_slice<'a>(self, n: usize) -> Option<Self::Slice<'a>>;
}

impl<T> CArray for *const T {
    type Slice<'a>
        = &'a [T]
    where
        T: 'a;

    unsafe fn to_slice<'a>(self, n: usize) -> Option<&'a [T]> {
        // SAFETY: forwarded from the contract.
        unsafe { slice(self, n) }
    }
}

impl<T> CArray for *mut T {
    type Slice<'a>
        = &'a mut [T]
    where
        T: 'a;

    unsafe fn to_slice<'a>(self, n: usize) -> Option<&'a mut [T]> {
        // SAFETY: forwarded from the contract.
        unsafe { slice_mut(self, n) }
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
    fn panics_inside_calls_are_recorded_with_their_location() {
        install_panic_hook();
        let line = line!() + 1;
        let outcome = catch_quietly(|| -> Status { panic!("min > max") });
        let message = outcome.unwrap_err();
        assert!(
            message.starts_with("min > max at ") && message.ends_with(&format!(":{line}")),
            "{message}"
        );
        assert_eq!(CALL_DEPTH.with(Cell::get), 0);
    }

    #[test]
    fn null_instance_is_an_error_not_a_crash() {
        // SAFETY: NULL is allowed by the contract.
        let status = unsafe {
            with_instance(
                std::ptr::null_mut(),
                crate::call_sequence::Call::DoStep,
                |_| Status::Ok,
            )
        };
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
