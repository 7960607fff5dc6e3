//! The one formatter of human-readable numbers, at the bottom of the layers so that error
//! messages ([`crate::error`]) and text output ([`crate::present::text`], which re-exports it)
//! write numbers alike.
//!
//! Text output shows values at a precision a reader can use: [`DIGITS`] significant digits by
//! default, solver noise (below [`SNAP`] times the scale of the quantity) shown as `0`, and
//! exponent notation for very large or small magnitudes, so that no value prints as hundreds of
//! digits (Rust's `{}` writes `1e300` as 301 digits). JSON output does not use this.

/// Significant digits of a value in text output unless the quantity asks for others: enough for
/// an objective or a displacement to be compared, few enough to hide the last bits of floating
/// point (`1.0000000000005613` shows as `1`).
pub const DIGITS: usize = 10;

/// A value smaller in magnitude than `SNAP` times the scale of its quantity is solver or
/// rounding noise: text shows it as `0`.
pub const SNAP: f64 = 1e-9;

/// `v` for text output, the one formatter of every human-readable number:
/// - `0` when `|v| < SNAP * scale` (the scale of the quantity: e.g. the rate bound for a
///   control, the period for a time; `0` never snaps), and for `-0`;
/// - otherwise rounded to `digits` significant digits (1 to 17), trailing zeros dropped;
/// - positional when the rounded value has a decimal exponent in `-5..digits`
///   (`2.5625`, `0.00015`, `1000000`), in Rust's exponent notation otherwise (`1e300`,
///   `-1.5e-7`, `1.234567891e10`);
/// - `NaN`, `inf` and `-inf` as such.
pub fn number(v: f64, scale: f64, digits: usize) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    let snaps = scale.is_finite() && scale > 0.0 && v.abs() < SNAP * scale;
    if v == 0.0 || snaps {
        return "0".into();
    }
    let digits = digits.clamp(1, 17);
    // Rounding by the standard library's exponent formatting: "d.ddde-7".
    let e = format!("{:.*e}", digits - 1, v);
    let Some((mantissa, exp)) = e.split_once('e') else {
        return format!("{v:e}");
    };
    let Ok(exp) = exp.parse::<i32>() else {
        return format!("{v:e}");
    };
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    // The significant digits, trailing zeros dropped (at least one digit stays).
    let sig: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let sig = match sig.trim_end_matches('0') {
        "" => "0",
        s => s,
    };
    if !(-5..digits as i32).contains(&exp) {
        let (first, rest) = sig.split_at(1);
        return if rest.is_empty() {
            format!("{sign}{first}e{exp}")
        } else {
            format!("{sign}{first}.{rest}e{exp}")
        };
    }
    if exp < 0 {
        let zeros = "0".repeat((-exp - 1) as usize);
        return format!("{sign}0.{zeros}{sig}");
    }
    // 0 <= exp < digits: the first exp + 1 digits are the integer part.
    let int_len = exp as usize + 1;
    if sig.len() <= int_len {
        format!("{sign}{sig}{}", "0".repeat(int_len - sig.len()))
    } else {
        let (int, frac) = sig.split_at(int_len);
        format!("{sign}{int}.{frac}")
    }
}

/// [`number`] with [`DIGITS`] significant digits.
pub fn num(v: f64, scale: f64) -> String {
    number(v, scale, DIGITS)
}
