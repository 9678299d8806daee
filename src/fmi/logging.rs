//! Log categories, the messages an instance collects during a call, and which categories
//! are switched on.
//!
//! An instance never calls the logger itself: it collects [`Message`]s, and the C layer
//! passes them to the master's logger once the call is over and the instance is no longer
//! borrowed (so a logger that calls back into the FMU finds it in a consistent state).

use super::types::Status;
use crate::fmu::description::LOG_CATEGORIES;

/// A log category declared in `modelDescription/fixed.xml`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// `logStatusWarning`.
    Warning,
    /// `logStatusError`.
    Error,
    /// `logStatusFatal`.
    Fatal,
    /// `logEvents`.
    Events,
    /// `logCalls`.
    Calls,
}

impl Category {
    /// The category name in the model description.
    pub fn name(self) -> &'static str {
        match self {
            Category::Warning => "logStatusWarning",
            Category::Error => "logStatusError",
            Category::Fatal => "logStatusFatal",
            Category::Events => "logEvents",
            Category::Calls => "logCalls",
        }
    }
}

/// One message for the master's logger.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    /// Status passed to the logger.
    pub status: Status,
    /// Category.
    pub category: Category,
    /// Plain text (the C layer escapes `%` for the printf-like logger).
    pub text: String,
}

/// Which categories are logged. Errors and fatal errors always are.
#[derive(Clone, Debug)]
pub(crate) struct LogSwitches {
    logging_on: bool,
    categories: Vec<bool>,
}

impl LogSwitches {
    /// Every category on or off (`loggingOn` of fmi2Instantiate).
    pub(crate) fn new(logging_on: bool) -> LogSwitches {
        LogSwitches {
            logging_on,
            categories: vec![true; LOG_CATEGORIES.len()],
        }
    }

    pub(crate) fn enabled(&self, category: Category) -> bool {
        match category {
            Category::Error | Category::Fatal => true,
            _ => {
                self.logging_on
                    && LOG_CATEGORIES
                        .iter()
                        .position(|(c, _)| *c == category.name())
                        .is_some_and(|i| self.categories[i])
            }
        }
    }

    /// fmi2SetDebugLogging: all categories (none named) or the named ones.
    pub(crate) fn set(&mut self, on: bool, names: &[&str]) -> Result<(), String> {
        let mut indices = Vec::with_capacity(names.len());
        for name in names {
            let i = LOG_CATEGORIES
                .iter()
                .position(|(c, _)| c == name)
                .ok_or_else(|| format!("unknown log category '{name}'"))?;
            indices.push(i);
        }
        if indices.is_empty() {
            self.categories.iter_mut().for_each(|c| *c = on);
            self.logging_on = on;
        } else {
            for i in indices {
                self.categories[i] = on;
            }
            self.logging_on = self.categories.iter().any(|c| *c);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_category_is_declared_in_the_model_description() {
        use Category::*;
        for c in [Warning, Error, Fatal, Events, Calls] {
            assert!(LOG_CATEGORIES.iter().any(|(n, _)| *n == c.name()), "{c:?}");
        }
    }

    #[test]
    fn errors_are_always_logged_the_rest_when_switched_on() {
        let mut s = LogSwitches::new(false);
        assert!(s.enabled(Category::Error) && s.enabled(Category::Fatal));
        assert!(!s.enabled(Category::Calls));
        s.set(true, &["logCalls"]).unwrap();
        assert!(s.enabled(Category::Calls));
        s.set(false, &[]).unwrap();
        assert!(!s.enabled(Category::Calls) && !s.enabled(Category::Events));
        s.set(true, &[]).unwrap();
        assert!(s.enabled(Category::Events));
        assert!(s.set(true, &["logCalls", "nonsense"]).is_err());
    }

    #[test]
    fn the_error_category_says_what_a_failed_call_does() {
        let (_, description) = LOG_CATEGORIES
            .iter()
            .find(|(c, _)| *c == Category::Error.name())
            .unwrap();
        // docs/DESIGN-NOTES.md, "Errors": refused calls keep the phase, failed calls keep
        // the model state and enter the error phase.
        assert!(description.contains("error phase"), "{description}");
        assert!(!description.contains("instance state is unchanged"));
    }
}
