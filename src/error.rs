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

    /// The uniqueness condition (SPEC §2, paper eq. 3.5) fails for the subset `subset`
    /// (1-based block numbers): a group of blocks can slide rigidly against the rest.
    #[error(
        "uniqueness condition (paper eq. 3.5) fails for blocks J = {subset:?}: \
         sum of mu_forward over J = {forward_sum} equals sum of mu_backward over the other blocks = {backward_sum}; \
         the motion is not unique (change a friction coefficient)"
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
    #[error("uniqueness condition (paper eq. 3.5) cannot be decided: {0}")]
    UniquenessUndecided(String),

    /// A state outside the polytope C of admissible spring forces (SPEC §2).
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
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}
