//! Writing a model file: the `[crawler]` section of a crawler (what `crawlopt fit` writes, and
//! `simulate`/`optimize` read once an `[actuation]` or a `[gait]` is added).

use super::config::CrawlerSpec;
use super::csv_io::AtomicFile;
use crate::error::{Error, Result};
use crate::fit::FitData;
use crate::model::Crawler;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// The `[crawler]` section of `crawler`, preceded by `comments` (one `# ` line each), written by
/// the model file's own serialiser ([`CrawlerSpec::of`]), so numbers read back to the same
/// doubles.
pub fn crawler_toml(crawler: &Crawler, comments: &[String]) -> Result<String> {
    #[derive(Serialize)]
    struct Section {
        crawler: CrawlerSpec,
    }
    let body = toml::to_string(&Section {
        crawler: CrawlerSpec::of(crawler),
    })
    .map_err(|e| Error::Io {
        path: "<model>".into(),
        reason: format!("cannot write the crawler as TOML: {e}"),
    })?;
    let mut s = String::new();
    for c in comments {
        for line in c.lines() {
            s += &format!("# {}\n", super::escape_controls(line));
        }
    }
    Ok(s + &body)
}

/// Writes `text` to `path` atomically (the file appears whole or not at all).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
    f.commit()
}

/// Largest trajectory CSV read by `crawlopt fit` (bytes).
pub const MAX_FIT_CSV_BYTES: u64 = 256 << 20;

/// Reads a measured trajectory (`t,L_1..L_n,X_1..X_N`) of a `blocks`-block crawler from a CSV
/// file; errors name the file, the column and the row.
pub fn read_fit_csv(path: &Path, blocks: usize) -> Result<FitData> {
    let text = super::read_input_text(path, MAX_FIT_CSV_BYTES)?;
    FitData::from_csv(&text, &path.display().to_string(), blocks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::ModelFile;

    #[test]
    fn a_written_crawler_reads_back_the_same() {
        let c = Crawler::new(
            vec![0.1 + 0.2, 1e-20],
            vec![1.0, 2.5, 3.0],
            vec![1e300, 0.7, 2.0],
        )
        .unwrap();
        let text = crawler_toml(&c, &["fitted\nby a test".into()]).unwrap();
        assert!(
            text.starts_with("# fitted\n# by a test\n[crawler]"),
            "{text}"
        );
        let back = ModelFile::parse(&text).unwrap().crawler().unwrap();
        assert_eq!(back, c);
    }
}
