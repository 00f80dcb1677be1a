//! The FMI status codes and the host's logger: FMI 2.0's called as
//! `logger(env, instanceName, status, category, "%s", message)` so that a `%` in a message is
//! never read as a format directive, FMI 3.0's as `logMessage(env, status, category, message)`.

use std::ffi::{CString, c_char, c_void};

use fmi_sys::fmi2::{fmi2ComponentEnvironment, fmi2Status, fmi2String};
use fmi_sys::fmi3::{fmi3InstanceEnvironment, fmi3Status, fmi3String};

use crate::variables::{LOG_CATEGORIES, LogCategory};

/// The host's FMI 2.0 logging function (never NULL here: checked at instantiation).
pub(crate) type LoggerFn = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// The host's FMI 3.0 logging function.
pub(crate) type LogMessageFn =
    unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String);

/// The host's logging function, of either standard.
#[derive(Clone, Copy)]
pub(crate) enum Callback {
    Fmi2(LoggerFn),
    /// FMI 3.0 allows no logger (NULL): nothing is reported then.
    Fmi3(Option<LogMessageFn>),
}

/// FMI status codes, in order of severity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u32)]
pub(crate) enum Status {
    Ok = fmi_sys::fmi2::fmi2Status_fmi2OK,
    Warning = fmi_sys::fmi2::fmi2Status_fmi2Warning,
    Discard = fmi_sys::fmi2::fmi2Status_fmi2Discard,
    Error = fmi_sys::fmi2::fmi2Status_fmi2Error,
    /// Never returned (after an internal failure the instance is in the Error state and can
    /// be reset). Kept: without it `Status::max` in the fmi2SetReal loop compiles differently.
    #[expect(dead_code, reason = "this FMU never returns fmi2Fatal")]
    Fatal = fmi_sys::fmi2::fmi2Status_fmi2Fatal,
}

/// The host's logger with the instance's name and the enabled categories.
pub(crate) struct Logger {
    callback: Callback,
    environment: *mut c_void,
    instance_name: CString,
    /// One bit per [`LogCategory`].
    enabled: u8,
}

impl Logger {
    /// `logging_on` enables every category but the verbose `logCalls`.
    pub(crate) fn new(
        callback: Callback,
        environment: *mut c_void,
        instance_name: CString,
        logging_on: bool,
    ) -> Self {
        let mut logger = Logger {
            callback,
            environment,
            instance_name,
            enabled: 0,
        };
        if logging_on {
            for (_, c) in LOG_CATEGORIES {
                if *c != LogCategory::Calls {
                    logger.enabled |= bit(*c);
                }
            }
        }
        logger
    }

    pub(crate) fn instance_name(&self) -> &str {
        self.instance_name.to_str().unwrap_or("?")
    }

    pub(crate) fn set_enabled(&mut self, category: LogCategory, on: bool) {
        if on {
            self.enabled |= bit(category);
        } else {
            self.enabled &= !bit(category);
        }
    }

    pub(crate) fn set_all(&mut self, on: bool) {
        for (_, c) in LOG_CATEGORIES {
            self.set_enabled(*c, on);
        }
    }

    /// Errors are always logged; other categories only when enabled.
    pub(crate) fn is_enabled(&self, category: LogCategory) -> bool {
        category == LogCategory::StatusError || self.enabled & bit(category) != 0
    }

    /// Sends `message` to the host if `category` is enabled.
    pub(crate) fn log(&self, status: Status, category: LogCategory, message: &str) {
        if !self.is_enabled(category) {
            return;
        }
        let message = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
        let category = CString::new(category.name()).unwrap_or_default();
        match self.callback {
            // SAFETY: the callback was checked non-NULL at instantiation and is called with
            // valid NUL-terminated strings that outlive the call; "%s" consumes exactly one
            // string.
            Callback::Fmi2(callback) => unsafe {
                callback(
                    self.environment,
                    self.instance_name.as_ptr(),
                    status as fmi2Status,
                    category.as_ptr(),
                    c"%s".as_ptr() as *const c_char,
                    message.as_ptr(),
                );
            },
            // SAFETY: the host's callback, called with valid NUL-terminated strings that
            // outlive the call. The status codes of both standards agree (OK 0 to Fatal 4).
            Callback::Fmi3(Some(callback)) => unsafe {
                callback(
                    self.environment,
                    status as fmi3Status,
                    category.as_ptr(),
                    message.as_ptr(),
                );
            },
            Callback::Fmi3(None) => {}
        }
    }
}

/// The bit of `category` in [`Logger`]'s enabled set.
fn bit(category: LogCategory) -> u8 {
    1 << category as u8
}
