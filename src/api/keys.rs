//! A table of keys read into a settings struct (a sweep file's `[settings]`, Python's keyword
//! arguments): each refusal names its key by its path (`bound.resolution`) and shows its value,
//! and a value of the wrong type is told apart from a wrong value by serde itself
//! ([`Error::WrongType`], Python's `TypeError`), not by the words of its message.

use crate::error::{Error, Result};
use serde::de::{DeserializeOwned, Expected, Unexpected};
use std::fmt;

/// `keys` as a `T`, whose every key is optional (a key left out takes its default). A key that
/// is none of `T`'s (its serde names, aliases included) is refused naming `settings` and
/// listing `T`'s keys.
pub(crate) fn read_keys<T: DeserializeOwned>(keys: &toml::Table) -> Result<T> {
    // The keys serde reads, aliases included, from the derived impl itself.
    let names = serde_aux::serde_introspection::serde_introspect::<T>();
    if let Some(key) = keys.keys().find(|k| !names.contains(&k.as_str())) {
        let settings: Vec<&str> = names.iter().copied().filter(|n| !n.contains('-')).collect();
        return Err(Error::invalid(
            "settings",
            "the table given",
            format!(
                "`{}` is not a setting (the settings are {})",
                crate::io::escape_controls(key),
                settings.join(", ")
            ),
        ));
    }
    let value = serde_value::to_value(keys)
        .map_err(|e| Error::invalid("settings", "the table given", e.to_string()))?;
    let de = serde_value::ValueDeserializer::<KeyError>::new(value);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let key = e.path().to_string();
        let inner = e.into_inner();
        let reason = crate::io::escape_controls(inner.message.trim());
        // The value at the key's path (`bound.resolution` inside the table `bound`).
        let value = key
            .split('.')
            .try_fold(None, |at: Option<&toml::Value>, k| {
                at.map_or_else(|| keys.get(k), |v| v.get(k)).map(Some)
            })
            .flatten();
        match value {
            Some(value) if inner.wrong_type => Error::wrong_type(key, value, reason),
            Some(value) => Error::invalid(key, value, reason),
            None => Error::invalid("settings", "the table given", reason),
        }
    })
}

/// serde's error while reading keys: its message in serde's own words, and whether serde
/// called it a value of the wrong type ([`serde::de::Error::invalid_type`]).
#[derive(Debug)]
struct KeyError {
    message: String,
    wrong_type: bool,
}

impl fmt::Display for KeyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for KeyError {}

impl serde::de::Error for KeyError {
    fn custom<T: fmt::Display>(message: T) -> Self {
        KeyError {
            message: message.to_string(),
            wrong_type: false,
        }
    }

    /// In serde's default words (`invalid type: string "three", expected u32`).
    fn invalid_type(unexpected: Unexpected<'_>, expected: &dyn Expected) -> Self {
        KeyError {
            message: format!("invalid type: {unexpected}, expected {expected}"),
            wrong_type: true,
        }
    }
}
