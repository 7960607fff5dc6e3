//! Value parsers of the flags: messages that say why a value is refused.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use crawlopt::api::GaitMethod;
use crawlopt::integrate::Method;

/// `--method`: one of the library's methods ([`GaitMethod::ALL`]), by its name, listed in
/// `--help` with the library's summary of each (clap names the flag and the values where one
/// is refused).
pub fn method() -> impl TypedValueParser<Value = GaitMethod> {
    PossibleValuesParser::new(
        GaitMethod::ALL.map(|m| PossibleValue::new(m.name()).help(m.summary())),
    )
    .try_map(|name| GaitMethod::from_name(&name))
}

/// `simulate --method`: one of the library's integration methods ([`Method::ALL`]), as
/// [`method`].
pub fn sim_method() -> impl TypedValueParser<Value = Method> {
    PossibleValuesParser::new(Method::ALL.map(|m| PossibleValue::new(m.name()).help(m.summary())))
        .try_map(|name| Method::from_name(&name))
}

/// A count flag (`--m`, `--phases`, `--periods`, ...): a whole number, 0 or more. Parsed here
/// so that the message says why a value is refused (std's "invalid digit found in string" for
/// `-1` does not); clap names the flag.
pub fn count(s: &str) -> Result<usize, String> {
    whole(s, usize::MAX as u64).map(|v| v as usize)
}

/// [`count`] for a `u32` flag (`--m`).
pub fn count_u32(s: &str) -> Result<u32, String> {
    whole(s, u32::MAX.into()).map(|v| v as u32)
}

/// A whole number in `0..=max`.
fn whole(s: &str, max: u64) -> Result<u64, String> {
    let too_large = || format!("too large (at most {max})");
    match s.parse::<u64>() {
        Ok(v) if v <= max => Ok(v),
        Ok(_) => Err(too_large()),
        Err(e) if *e.kind() == std::num::IntErrorKind::PosOverflow => Err(too_large()),
        Err(_) if s.parse::<f64>().is_ok_and(|v| v < 0.0) => {
            Err("must not be negative (a whole number, 0 or more)".into())
        }
        Err(_) => Err("not a whole number (0, 1, 2, ...)".into()),
    }
}
