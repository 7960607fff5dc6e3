//! A problem file of either kind ([`ProblemFile`]): a crawler's model file or a general
//! problem (P), told apart by its content.

use super::config::ModelFile;
use super::general::GeneralFile;
use crate::error::Result;

/// A problem file of either kind, told apart by its content ([`ProblemFile::load`]): a file
/// with a `[sweeping_process]` table is a general problem (P) ([`GeneralFile`], theory §11),
/// any other a crawler's model file ([`ModelFile`]). The one loader of the commands that take
/// both kinds.
#[derive(Debug, Clone)]
pub enum ProblemFile {
    /// A crawler's model file.
    Crawler(Box<ModelFile>),
    /// A general problem file.
    General(Box<GeneralFile>),
}

impl ProblemFile {
    /// Reads a problem file of either kind; errors as [`GeneralFile::load_if_general`] and
    /// [`ModelFile::load`] give them.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        Ok(match GeneralFile::load_if_general(path)? {
            Some(g) => ProblemFile::General(Box::new(g)),
            None => ProblemFile::Crawler(Box::new(ModelFile::load(path)?)),
        })
    }
}
