//! CSV actuations (`t, L_1, .., L_n` per knot) and trajectories, and atomic output files.

use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use std::io::Write;
use std::path::{Path, PathBuf};

fn io_err(path: &Path, e: impl ToString) -> Error {
    Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Reads a piecewise-linear actuation from CSV: one row per knot, columns `t, L_1, .., L_n`
/// (a header row is recognised by a non-numeric first field and skipped).
pub fn read_actuation_csv(path: &Path, links: usize) -> Result<(Vec<f64>, Vec<Vec<f64>>)> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| io_err(path, format!("cannot read actuation CSV: {e}")))?;
    let (mut times, mut lengths) = (Vec::new(), Vec::new());
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| io_err(path, format!("invalid CSV: {e}")))?;
        let row = i + 1;
        if i == 0 && rec.get(0).is_some_and(|f| f.parse::<f64>().is_err()) {
            continue; // header
        }
        if rec.len() != links + 1 {
            return Err(io_err(
                path,
                format!(
                    "row {row}: {} columns, expected {} (t and one length per link)",
                    rec.len(),
                    links + 1
                ),
            ));
        }
        let vals = rec
            .iter()
            .enumerate()
            .map(|(c, f)| {
                f.parse::<f64>().map_err(|_| {
                    io_err(
                        path,
                        format!("row {row}, column {}: not a number: {f:?}", c + 1),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        times.push(vals[0]);
        lengths.push(vals[1..].to_vec());
    }
    if times.is_empty() {
        return Err(io_err(path, "the actuation CSV has no data rows"));
    }
    Ok((times, lengths))
}

/// A file written under a temporary name and renamed into place on [`AtomicFile::commit`];
/// dropped without commit, it leaves nothing behind.
pub struct AtomicFile {
    tmp: PathBuf,
    dest: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Creates the temporary file next to `dest`.
    pub fn create(dest: &Path) -> Result<Self> {
        let name = dest
            .file_name()
            .ok_or_else(|| io_err(dest, "not a file name"))?
            .to_string_lossy()
            .into_owned();
        let tmp = dest.with_file_name(format!(".{name}.tmp{}", std::process::id()));
        let file =
            std::fs::File::create(&tmp).map_err(|e| io_err(dest, format!("cannot write: {e}")))?;
        Ok(AtomicFile {
            tmp,
            dest: dest.to_path_buf(),
            file: Some(std::io::BufWriter::new(file)),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut std::io::BufWriter<std::fs::File> {
        self.file.as_mut().expect("file open until commit")
    }

    /// Flushes and renames into place.
    pub fn commit(mut self) -> Result<()> {
        let mut f = self.file.take().expect("file open until commit");
        f.flush().map_err(|e| io_err(&self.dest, e))?;
        drop(f);
        std::fs::rename(&self.tmp, &self.dest).map_err(|e| io_err(&self.dest, e))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.is_some() {
            self.file = None;
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes a trajectory as CSV: `t, x_1..x_n, X_1..X_N, y, slip_1..slip_N` (1-based names).
pub fn write_trajectory_csv(path: &Path, traj: &Trajectory) -> Result<()> {
    let mut out = AtomicFile::create(path)?;
    let n = traj.x.first().map_or(0, Vec::len);
    let nb = traj.positions.first().map_or(0, Vec::len);
    {
        let mut w = csv::Writer::from_writer(out.writer());
        let mut header = vec!["t".to_string()];
        header.extend((1..=n).map(|l| format!("x_{l}")));
        header.extend((1..=nb).map(|b| format!("X_{b}")));
        header.push("y".into());
        header.extend((1..=nb).map(|b| format!("slip_{b}")));
        w.write_record(&header).map_err(|e| io_err(path, e))?;
        for i in 0..traj.t.len() {
            let mut row = vec![format!("{}", traj.t[i])];
            row.extend(traj.x[i].iter().map(|v| format!("{v}")));
            row.extend(traj.positions[i].iter().map(|v| format!("{v}")));
            row.push(format!("{}", traj.barycentre[i]));
            row.extend(traj.slip[i].iter().map(|v| v.to_string()));
            w.write_record(&row).map_err(|e| io_err(path, e))?;
        }
        w.flush().map_err(|e| io_err(path, e))?;
    }
    out.commit()
}
