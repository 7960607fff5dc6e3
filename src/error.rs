//! Typed errors of the library. The CLI renders them as one line and exits with status 2.

use thiserror::Error;

/// Everything that can make a model, an actuation or a simulation ill-posed.
///
/// Every variant names the offending field or object and the value, so that a message such as
/// `crawler.mu_forward[2]: must be positive and finite (got -1)` can be shown as it is.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A parameter has a wrong value (non-positive, non-finite, out of range, wrong length...).
    #[error("{field}: {reason} (got {value})")]
    InvalidParameter {
        /// Path of the field, e.g. `crawler.stiffness[2]`.
        field: String,
        /// The value as given.
        value: String,
        /// What is wrong with it.
        reason: String,
    },

    /// A parameter has a value of the wrong type (a word where a number is read), as serde
    /// reading a table of keys found it (a sweep file's `[settings]`, Python's keywords, where
    /// it is a `TypeError`); said in the words of [`Error::InvalidParameter`].
    #[error("{field}: {reason} (got {value})")]
    WrongType {
        /// Path of the field, e.g. `bound.resolution`.
        field: String,
        /// The value as given.
        value: String,
        /// What type was expected (serde's words).
        reason: String,
    },

    /// The uniqueness condition (theory §2, paper eq. 3.6) fails for the subset `subset`
    /// (1-based block numbers): a group of blocks can slide rigidly against the rest.
    #[error(
        "uniqueness condition (paper eq. 3.6) fails for blocks J = {}: \
         sum of mu_forward over J = {} equals sum of mu_backward over the other blocks = {} \
         (within a relative 1e-9); the motion is not unique (change a friction coefficient)",
        subset_text(.subset),
        sum_text(.forward_sum),
        sum_text(.backward_sum)
    )]
    NonUnique {
        /// The violating subset J, 1-based block numbers.
        subset: Vec<usize>,
        /// Sum of mu^+ over J.
        forward_sum: f64,
        /// Sum of mu^- over the complement of J.
        backward_sum: f64,
    },

    /// The uniqueness condition could not be decided within the enumeration limits.
    #[error("uniqueness condition (paper eq. 3.6) cannot be decided: {0}")]
    UniquenessUndecided(String),

    /// A state outside the polytope C of admissible spring forces (theory §2).
    #[error("{what}: state is not admissible (outside C): {detail}")]
    Inadmissible {
        /// Which state, e.g. `simulation.initial_state`.
        what: String,
        /// The violated face and by how much.
        detail: String,
    },

    /// A numerical kernel did not terminate within its iteration budget.
    #[error("{0}")]
    Numerical(String),

    /// A time limit ended a computation before it had any answer to return.
    #[error("{0}")]
    TimeLimit(String),

    /// An optimisation problem has no feasible point (e.g. a fixed sequence of slip modes that
    /// no gait of the period can follow).
    #[error("{0}")]
    Infeasible(String),

    /// The caller cancelled the job ([`crate::progress::Cancel`]); it stopped at its next check
    /// (between MILPs, periods or iterations, or inside a running MILP through HiGHS's
    /// interrupt callback) without an answer.
    #[error("cancelled")]
    Cancelled,

    /// Reading or writing a file failed.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's or parser's message.
        reason: String,
    },
}

/// Result alias of the library.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            value: shown(value.to_string()),
            reason: reason.into(),
        }
    }

    /// This error with the field it names mapped by `f` (the field of an
    /// [`Error::InvalidParameter`] or an [`Error::WrongType`]; other errors name no field and
    /// are returned as they are): how a caller names a field at its own place, e.g. a result
    /// file's `r.json: problem.gait.period` for a model's `gait.period`.
    pub fn map_field(self, f: impl FnOnce(String) -> String) -> Self {
        match self {
            Error::InvalidParameter {
                field,
                value,
                reason,
            } => Error::InvalidParameter {
                field: f(field),
                value,
                reason,
            },
            Error::WrongType {
                field,
                value,
                reason,
            } => Error::WrongType {
                field: f(field),
                value,
                reason,
            },
            other => other,
        }
    }

    /// Shorthand for [`Error::WrongType`], its value shown as [`Error::invalid`] shows one.
    pub(crate) fn wrong_type(field: String, value: impl ToString, reason: String) -> Self {
        Error::WrongType {
            field,
            value: shown(value.to_string()),
            reason,
        }
    }
}

/// A friction sum of [`Error::NonUnique`], as text output shows numbers (no snapping: these are
/// sums of inputs).
/// A subset of blocks for a one-line message: in full up to 12 blocks, else its first and last
/// five and how many (a long chain's subset would fill screens).
fn subset_text(subset: &[usize]) -> String {
    if subset.len() <= 12 {
        return format!("{subset:?}");
    }
    let show = |v: &[usize]| {
        v.iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "[{}, ..., {}] ({} blocks)",
        show(&subset[..5]),
        show(&subset[subset.len() - 5..]),
        subset.len()
    )
}

fn sum_text(v: &f64) -> String {
    crate::number::num(*v, 0.0)
}

/// A value as given, except a number that `{}` wrote out in tens or hundreds of digits
/// (`1e-300` as 0.000...0001): that one in exponent form, which is exact (`1e-300`).
fn shown(value: String) -> String {
    match value.parse::<f64>() {
        Ok(v) if value.len() > 24 && v.is_finite() => format!("{v:e}"),
        _ => value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_numbers_are_shown_in_exponent_form() {
        let e = Error::invalid(
            "crawler.mu_forward[1]",
            -1e-300,
            "must be positive and finite",
        );
        assert_eq!(
            e.to_string(),
            "crawler.mu_forward[1]: must be positive and finite (got -1e-300)"
        );
        let e = Error::invalid("x", 1e300, "too large");
        assert_eq!(e.to_string(), "x: too large (got 1e300)");
        // Short values and non-numbers are shown as given.
        assert_eq!(
            Error::invalid("x", 0.25, "r").to_string(),
            "x: r (got 0.25)"
        );
        assert_eq!(
            Error::invalid("x", "a file", "r").to_string(),
            "x: r (got a file)"
        );
        let long = "a name that is longer than twenty-four characters";
        assert!(Error::invalid("x", long, "r").to_string().contains(long));
    }

    #[test]
    fn the_uniqueness_message_rounds_its_sums() {
        let e = Error::NonUnique {
            subset: vec![1, 2],
            forward_sum: 0.30000000000000004,
            backward_sum: -0.0 + 0.3,
        };
        let text = e.to_string();
        assert!(text.contains("J = [1, 2]"), "{text}");
        assert!(text.contains("over J = 0.3 equals"), "{text}");
        assert!(text.contains("other blocks = 0.3 "), "{text}");
        let e = Error::NonUnique {
            subset: vec![1],
            forward_sum: -0.0,
            backward_sum: 1e-300,
        };
        assert!(e.to_string().contains("over J = 0 equals"), "{e}");
        assert!(e.to_string().contains("= 1e-300 "), "{e}");
    }
}
