//! Log categories and the filter that decides which messages reach the importer's logger.
//!
//! Policy: messages with status Warning, Discard, Error or Fatal always reach the logger (they
//! explain a status the importer receives); informational messages only when logging is on and
//! their category is enabled (`loggingOn`, `fmi2SetDebugLogging`).

/// Status of a message, mirroring fmi2Status.
///
/// `#[must_use]`: a status that nobody looks at hides a rejected call (a parameter that was
/// refused silently runs at its default).
#[must_use = "a discarded status hides a rejected FMI call"]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// fmi2OK
    Ok,
    /// fmi2Warning
    Warning,
    /// fmi2Discard
    Discard,
    /// fmi2Error
    Error,
    /// fmi2Fatal
    Fatal,
}

/// Declared log categories `(name, description)`, in the order of the model description.
pub const CATEGORIES: &[(&str, &str)] = &[
    (
        "logEvents",
        "Initialization, static solves, parameter changes",
    ),
    (
        "logNonlinearSystems",
        "Newton iterations and step-size cuts",
    ),
    ("logCalls", "Every FMI function call with its arguments"),
    ("logStatusWarning", "Messages with status fmi2Warning"),
    ("logStatusDiscard", "Messages with status fmi2Discard"),
    ("logStatusError", "Messages with status fmi2Error"),
    ("logStatusFatal", "Messages with status fmi2Fatal"),
];

/// Category of a message with the given status.
pub fn status_category(status: Status) -> &'static str {
    match status {
        Status::Ok => "logEvents",
        Status::Warning => "logStatusWarning",
        Status::Discard => "logStatusDiscard",
        Status::Error => "logStatusError",
        Status::Fatal => "logStatusFatal",
    }
}

/// Which categories are on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogFilter {
    on: bool,
    enabled: Vec<bool>,
}

impl LogFilter {
    /// `loggingOn` from fmi2Instantiate: all categories on or off.
    pub fn new(logging_on: bool) -> Self {
        Self {
            on: logging_on,
            enabled: vec![true; CATEGORIES.len()],
        }
    }

    /// fmi2SetDebugLogging: with no categories, all are switched; otherwise only those listed
    /// are enabled (and logging is switched as asked). Unknown names are returned as an error.
    pub fn set(&mut self, logging_on: bool, categories: &[&str]) -> Result<(), String> {
        let mut idx = Vec::new();
        for c in categories {
            match CATEGORIES.iter().position(|(n, _)| n == c) {
                Some(i) => idx.push(i),
                None => {
                    return Err(format!(
                        "fmi2SetDebugLogging: unknown log category \"{c}\"; declared: {}",
                        CATEGORIES
                            .iter()
                            .map(|(n, _)| *n)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
            }
        }
        if categories.is_empty() {
            self.on = logging_on;
            self.enabled.iter_mut().for_each(|e| *e = true);
        } else {
            if logging_on {
                self.on = true;
            }
            for i in idx {
                self.enabled[i] = logging_on;
            }
        }
        Ok(())
    }

    /// Whether a message of `status` in `category` is delivered.
    pub fn passes(&self, status: Status, category: &str) -> bool {
        if status >= Status::Warning {
            return true;
        }
        self.on
            && CATEGORIES
                .iter()
                .position(|(n, _)| *n == category)
                .is_some_and(|i| self.enabled[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_rules() {
        let mut f = LogFilter::new(false);
        assert!(!f.passes(Status::Ok, "logEvents"));
        assert!(
            f.passes(Status::Error, "logStatusError"),
            "errors always pass"
        );
        f.set(true, &[]).unwrap();
        assert!(f.passes(Status::Ok, "logEvents"));
        f.set(false, &["logEvents"]).unwrap();
        assert!(!f.passes(Status::Ok, "logEvents"));
        assert!(f.passes(Status::Ok, "logNonlinearSystems"));
        assert!(f.set(true, &["nope"]).is_err());
    }
}
