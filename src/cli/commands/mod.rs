//! One module per command: its arguments, and a `run` that translates them into the library's
//! settings, calls the library and renders the result.

pub mod analyze;
pub mod bench;
pub mod bound_flags;
pub mod certify;
pub mod fit;
pub mod optimize;
pub mod plot;
pub mod report;
pub mod simulate;
pub mod sweep;
