//! The one JSON writer of every front end (`--json`, Python's `to_json` and events): serde_json
//! with a formatter that writes `-0.0` as `0.0`. A solver's zero often carries a sign (HiGHS's
//! bound of an idle P_1 is `-0.0`), which means nothing and reads as a negative value; text output
//! drops it in [`crate::present::text::number`], JSON here.

use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter, PrettyFormatter};
use std::io::{self, Write};

/// A formatter that writes every floating-point zero as `0.0` and leaves the layout to `F`.
struct Unsigned<F>(F);

impl<F: Formatter> Formatter for Unsigned<F> {
    fn write_f64<W: ?Sized + Write>(&mut self, w: &mut W, v: f64) -> io::Result<()> {
        self.0.write_f64(w, if v == 0.0 { 0.0 } else { v })
    }
    fn write_f32<W: ?Sized + Write>(&mut self, w: &mut W, v: f32) -> io::Result<()> {
        self.0.write_f32(w, if v == 0.0 { 0.0 } else { v })
    }
    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_array(w)
    }
    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array(w)
    }
    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.0.begin_array_value(w, first)
    }
    fn end_array_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array_value(w)
    }
    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object(w)
    }
    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object(w)
    }
    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.0.begin_object_key(w, first)
    }
    fn end_object_key<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object_key(w)
    }
    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object_value(w)
    }
    fn end_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object_value(w)
    }
}

/// Writes `value` as indented JSON (no trailing newline), streaming: nothing is built in memory.
pub fn to_writer_pretty<W: Write>(w: W, value: &impl Serialize) -> serde_json::Result<()> {
    let mut ser = serde_json::Serializer::with_formatter(w, Unsigned(PrettyFormatter::new()));
    value.serialize(&mut ser)
}

/// `value` as compact JSON on one line, keys in the order of its type.
pub fn to_string(value: &impl Serialize) -> serde_json::Result<String> {
    let mut out = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut out, Unsigned(CompactFormatter));
    value.serialize(&mut ser)?;
    // serde_json writes UTF-8 only.
    Ok(String::from_utf8_lossy(&out).into_owned())
}

/// `value` as compact JSON on one line with the keys of its objects in alphabetical order
/// (through a `serde_json::Value`), as `optimize --json` has always printed.
pub fn to_string_sorted(value: &impl Serialize) -> serde_json::Result<String> {
    to_string(&serde_json::to_value(value)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 30, item 17: `"bound": -0.0` in `optimize --convergence --json`.
    #[test]
    fn negative_zero_is_written_as_zero_and_nothing_else_changes() {
        #[derive(Serialize)]
        struct Row {
            bound: f64,
            v: Vec<f64>,
            f: f32,
        }
        let r = Row {
            bound: -0.0,
            v: vec![-0.0, -1e-300, 1.5, -2.0, f64::MIN_POSITIVE],
            f: -0.0,
        };
        let s = to_string(&r).unwrap();
        assert_eq!(
            s,
            r#"{"bound":0.0,"v":[0.0,-1e-300,1.5,-2.0,2.2250738585072014e-308],"f":0.0}"#
        );
        assert_eq!(
            to_string_sorted(&r).unwrap(),
            r#"{"bound":0.0,"f":0.0,"v":[0.0,-1e-300,1.5,-2.0,2.2250738585072014e-308]}"#
        );
        let mut pretty = Vec::new();
        to_writer_pretty(&mut pretty, &r).unwrap();
        let pretty = String::from_utf8(pretty).unwrap();
        assert!(
            pretty.starts_with("{\n  \"bound\": 0.0,\n  \"v\": [\n    0.0,"),
            "{pretty}"
        );
        assert!(!pretty.contains("-0.0"));
        // What serde_json alone writes, so that this test fails without the formatter.
        assert!(serde_json::to_string(&r).unwrap().contains("-0.0"));
    }
}
