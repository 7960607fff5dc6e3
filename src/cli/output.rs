//! Standard output that ends the process quietly when it is closed (`crawlopt ... | head`),
//! and input files read with the library's bounds.

use crawlopt::Error;
use std::io::Write as _;
use std::path::Path;

/// Prints `text` as it is (a rendered block ending in a newline, or nothing).
pub fn out(text: &str) {
    let mut w = std::io::stdout().lock();
    finish(w.write_all(text.as_bytes()).and_then(|()| w.flush()));
}

/// Prints one line.
pub fn outln(line: &str) {
    out(&format!("{line}\n"));
}

/// Writes `value` as pretty JSON and a newline without building it in memory first.
pub fn write_json(value: &impl serde::Serialize) {
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let done = crawlopt::io::json::to_writer_pretty(&mut w, value)
        .map_err(std::io::Error::from)
        .and_then(|()| writeln!(w))
        .and_then(|()| w.flush());
    finish(done);
}

/// Prints `value` as compact JSON on one line, its keys in the order of its type.
pub fn json_line(value: &impl serde::Serialize) {
    outln(&crawlopt::io::json::to_string(value).expect("serialisable"));
}

/// Prints `value` as compact JSON on one line through a `serde_json::Value`, as `optimize`
/// and `bench` always have: its keys come out sorted.
pub fn json_line_sorted(value: &impl serde::Serialize) {
    outln(&crawlopt::io::json::to_string_sorted(value).expect("serialisable"));
}

/// Ends quietly on a closed pipe, with exit 2 and a message on another write error.
fn finish(r: std::io::Result<()>) {
    if let Err(e) = r {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write the output: {e}");
        std::process::exit(2);
    }
}

/// The text of an input file (errors name the file).
pub fn read_text(path: &Path) -> Result<String, Error> {
    crawlopt::io::read_input_text(path, crawlopt::io::MAX_RESULT_BYTES)
}

/// The file name of a path, for messages and the report (no directories).
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
