//! Messages to the importer's logger callback, filtered by log category.
//!
//! Policy (FMI 2.0 section 2.1.5 leaves errors open; this follows the
//! Reference-FMUs and the FMU SDK):
//! * messages with status `fmi2Discard`, `fmi2Error` or `fmi2Fatal` are
//!   **always** forwarded, whatever the debug-logging settings, because the
//!   importer gets a return it must act on and needs the reason (a discarded
//!   communication step would otherwise end a run with no word of why);
//! * every other message is forwarded only if its category is enabled, or
//!   `logAll` is enabled ("log all messages" in the standard's list of
//!   recommended categories).
//!
//! `fmi2Instantiate(loggingOn)` enables all categories or none.
//! `fmi2SetDebugLogging(loggingOn, nCategories, categories)`:
//! * `loggingOn = true,  n = 0`: all categories on;
//! * `loggingOn = true,  n > 0`: exactly the listed categories on, all others
//!   off ("only debug messages according to the categories argument");
//! * `loggingOn = false, n = 0`: all categories off;
//! * `loggingOn = false, n > 0`: the listed categories off, others unchanged.
//!
//! An unknown category name is an error and changes nothing.

use std::ffi::{CStr, CString};

use super::types::{Fmi2CallbackFunctions, Fmi2Status};

// Category names used by the plumbing; a model's <LogCategories> must list
// them all (PLUMBING_CATEGORIES).
/// State changes and other fmi2OK messages.
pub const LOG_EVENTS: &str = "logEvents";
/// Messages with status fmi2Warning.
pub const LOG_STATUS_WARNING: &str = "logStatusWarning";
/// Messages with status fmi2Discard.
pub const LOG_STATUS_DISCARD: &str = "logStatusDiscard";
/// Messages with status fmi2Error.
pub const LOG_STATUS_ERROR: &str = "logStatusError";
/// Messages with status fmi2Fatal.
pub const LOG_STATUS_FATAL: &str = "logStatusFatal";
/// Every message, including a trace of each call.
pub const LOG_ALL: &str = "logAll";

/// Every category the plumbing logs in.
pub const PLUMBING_CATEGORIES: [&str; 6] = [
    LOG_EVENTS,
    LOG_STATUS_WARNING,
    LOG_STATUS_DISCARD,
    LOG_STATUS_ERROR,
    LOG_STATUS_FATAL,
    LOG_ALL,
];

/// The plumbing's categories missing from a model's `categories`.
pub fn missing_categories(categories: &[&str]) -> Vec<&'static str> {
    PLUMBING_CATEGORIES
        .into_iter()
        .filter(|c| !categories.contains(c))
        .collect()
}

/// The category a message of this status belongs to; `fmi2OK` messages are
/// events (state changes).
pub fn category_of(status: Fmi2Status) -> &'static str {
    match status {
        Fmi2Status::Ok | Fmi2Status::Pending => LOG_EVENTS,
        Fmi2Status::Warning => LOG_STATUS_WARNING,
        Fmi2Status::Discard => LOG_STATUS_DISCARD,
        Fmi2Status::Error => LOG_STATUS_ERROR,
        Fmi2Status::Fatal => LOG_STATUS_FATAL,
    }
}

/// The logger callback and category switches of one instance.
pub struct Logger {
    callbacks: Fmi2CallbackFunctions,
    instance_name: CString,
    /// The model's `<LogCategories>`.
    categories: &'static [&'static str],
    /// One switch per entry of `categories`.
    enabled: Vec<bool>,
}

impl Logger {
    /// A logger for an instance of a model with these `<LogCategories>`.
    pub fn new(
        callbacks: Fmi2CallbackFunctions,
        instance_name: CString,
        logging_on: bool,
        categories: &'static [&'static str],
    ) -> Self {
        Logger {
            callbacks,
            instance_name,
            categories,
            enabled: vec![logging_on; categories.len()],
        }
    }

    /// The instance name given to fmi2Instantiate.
    pub fn instance_name(&self) -> &CStr {
        &self.instance_name
    }

    /// fmi2SetDebugLogging (see the module documentation).
    pub fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[&str],
    ) -> Result<(), String> {
        let mut indices = Vec::with_capacity(categories.len());
        for name in categories {
            let i = self
                .categories
                .iter()
                .position(|c| c == name)
                .ok_or_else(|| {
                    format!(
                        "unknown log category \"{name}\" (this FMU defines {})",
                        self.categories.join(", ")
                    )
                })?;
            indices.push(i);
        }
        if categories.is_empty() || logging_on {
            self.enabled.fill(logging_on && categories.is_empty());
        }
        for i in indices {
            self.enabled[i] = logging_on;
        }
        Ok(())
    }

    /// Whether a message in `category` would currently be forwarded
    /// (ignoring the always-forward rule for errors).
    pub fn is_enabled(&self, category: &str) -> bool {
        let on = |name: &str| {
            self.categories
                .iter()
                .position(|c| *c == name)
                .is_some_and(|i| self.enabled[i])
        };
        on(category) || on(LOG_ALL)
    }

    /// Emits `message` whatever the enabled categories: for the few
    /// messages a user must see even with logging off (a parameter warning
    /// at initialization).
    pub fn always(&self, status: Fmi2Status, category: &str, message: &str) {
        emit(
            &self.callbacks,
            &self.instance_name,
            status,
            category,
            message,
        );
    }

    /// Send `message` to the importer if the policy above allows it.
    pub fn log(&self, status: Fmi2Status, category: &str, message: &str) {
        let always = matches!(
            status,
            Fmi2Status::Discard | Fmi2Status::Error | Fmi2Status::Fatal
        );
        if always || self.is_enabled(category) {
            self.always(status, category, message);
        }
    }
}

/// Call the importer's logger (if any) unconditionally. Used by [`Logger`]
/// and by fmi2Instantiate before an instance exists.
pub fn emit(
    callbacks: &Fmi2CallbackFunctions,
    instance_name: &CStr,
    status: Fmi2Status,
    category: &str,
    message: &str,
) {
    let Some(logger) = callbacks.logger else {
        return; // a NULL logger means: stay silent
    };
    // The message is passed as the printf format with no arguments, so every
    // '%' must be doubled; NUL bytes would truncate the C string.
    let format = c_string(&message.replace('%', "%%"));
    let category = c_string(category);
    // SAFETY: `logger` is the importer's fmi2CallbackLogger (FMI 2.0 section
    // 2.1.5). All strings are valid, NUL-terminated and outlive the call; the
    // format contains no conversion specifiers, so no variadic arguments are
    // read.
    unsafe {
        logger(
            callbacks.component_environment,
            instance_name.as_ptr(),
            status,
            category.as_ptr(),
            format.as_ptr(),
        );
    }
}

/// A C string of `s` with any NUL byte replaced by U+FFFD.
pub fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\u{fffd}")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_plumbing_categories_are_found() {
        assert!(missing_categories(&PLUMBING_CATEGORIES).is_empty());
        assert_eq!(
            missing_categories(&[LOG_EVENTS, "logOther"]),
            &PLUMBING_CATEGORIES[1..]
        );
    }

    fn logger(on: bool) -> Logger {
        let callbacks = Fmi2CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: std::ptr::null_mut(),
        };
        Logger::new(callbacks, c_string("test"), on, &PLUMBING_CATEGORIES)
    }

    #[test]
    fn debug_logging_switches() {
        let mut l = logger(false);
        assert!(!l.is_enabled(LOG_EVENTS));
        l.set_debug_logging(true, &[]).unwrap();
        assert!(l.is_enabled(LOG_EVENTS) && l.is_enabled(LOG_STATUS_DISCARD));
        l.set_debug_logging(true, &[LOG_STATUS_DISCARD]).unwrap();
        assert!(!l.is_enabled(LOG_EVENTS) && l.is_enabled(LOG_STATUS_DISCARD));
        l.set_debug_logging(false, &[LOG_STATUS_DISCARD]).unwrap();
        assert!(!l.is_enabled(LOG_STATUS_DISCARD));
        l.set_debug_logging(true, &[LOG_ALL]).unwrap();
        assert!(l.is_enabled(LOG_EVENTS), "logAll enables everything");
        l.set_debug_logging(false, &[]).unwrap();
        assert!(!l.is_enabled(LOG_EVENTS));
        assert!(l.set_debug_logging(true, &["logNonsense"]).is_err());
        assert!(!l.is_enabled(LOG_EVENTS), "failed call changes nothing");
    }

    #[test]
    fn c_string_survives_nul() {
        assert_eq!(c_string("a\0b").to_str().unwrap(), "a\u{fffd}b");
    }
}
