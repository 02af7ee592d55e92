//! The named choices a model file, a command line and Python's keywords offer (a shaping family,
//! a k2 law, a form, a hold, …): each value's name, its one-line description and the old names
//! still read, in one table per choice. Model files read and write the same names through
//! serde; [`Choice::parse`] reads them from text (the CLI's flags, Python's keywords), and its
//! error lists the names.

use core::fmt;

/// A choice among a fixed set of named values.
///
/// `CHOICES` is the one list of the values, their names (kebab-case, as in a model file) and
/// descriptions; `ALIASES` holds older names that still read as a value.
pub trait Choice: Copy + PartialEq + 'static {
    /// What is chosen, in words for an error message ("shaping", "k2 law", …).
    const WHAT: &'static str;
    /// Every value with its name and a one-line description.
    const CHOICES: &'static [(Self, &'static str, &'static str)];
    /// Older names still read, with the value each reads as.
    const ALIASES: &'static [(&'static str, Self)] = &[];

    /// The value's name.
    fn name(self) -> &'static str {
        Self::CHOICES
            .iter()
            .find(|(v, _, _)| *v == self)
            .map_or("?", |(_, n, _)| n)
    }

    /// The value's one-line description.
    fn help(self) -> &'static str {
        Self::CHOICES
            .iter()
            .find(|(v, _, _)| *v == self)
            .map_or("", |(_, _, h)| h)
    }

    /// The value named `text` (a name of `CHOICES` or an alias); with `ignore_case`, ASCII
    /// letters match in either case.
    ///
    /// # Errors
    /// [`UnknownChoice`] naming the text and the possible names.
    fn parse(text: &str, ignore_case: bool) -> Result<Self, UnknownChoice> {
        let same = |name: &str| {
            if ignore_case {
                name.eq_ignore_ascii_case(text)
            } else {
                name == text
            }
        };
        Self::CHOICES
            .iter()
            .find(|(_, n, _)| same(n))
            .map(|(v, _, _)| *v)
            .or_else(|| Self::ALIASES.iter().find(|(n, _)| same(n)).map(|(_, v)| *v))
            .ok_or_else(|| UnknownChoice {
                what: Self::WHAT,
                text: text.to_string(),
                names: Self::CHOICES.iter().map(|(_, n, _)| *n).collect(),
            })
    }
}

/// A name that is none of a [`Choice`]'s.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownChoice {
    /// What is chosen ([`Choice::WHAT`]).
    pub what: &'static str,
    /// The text given.
    pub text: String,
    /// The possible names.
    pub names: Vec<&'static str>,
}

impl fmt::Display for UnknownChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} is no {}; possible values: {}",
            self.text,
            self.what,
            self.names.join(", ")
        )
    }
}

impl std::error::Error for UnknownChoice {}

#[cfg(test)]
pub(crate) mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::{Form, Hold, K2Kind, ModelKind, RateTerm, ShapingKind};

    /// Checks that serde reads and writes a choice by the names of its table: every value
    /// round-trips through its name and every alias reads as its value. For the tests of each
    /// choice (serde's derive spells the names a second time, in `rename_all`).
    pub(crate) fn assert_serde_names<C>()
    where
        C: Choice + fmt::Debug + serde::Serialize + serde::de::DeserializeOwned,
    {
        #[derive(serde::Serialize, serde::Deserialize)]
        struct Wrap<C> {
            v: C,
        }
        for (value, name, _) in C::CHOICES {
            let text = toml::to_string(&Wrap { v: *value }).unwrap();
            assert_eq!(text.trim(), format!("v = \"{name}\""), "{value:?}");
            assert_eq!(C::parse(name, false), Ok(*value));
        }
        for (alias, value) in C::ALIASES {
            let read: Wrap<C> = toml::from_str(&format!("v = \"{alias}\"")).unwrap();
            assert_eq!(read.v, *value, "{alias}");
        }
    }

    #[test]
    fn serde_and_the_tables_name_every_choice_alike() {
        assert_serde_names::<ShapingKind>();
        assert_serde_names::<K2Kind>();
        assert_serde_names::<RateTerm>();
        assert_serde_names::<Form>();
        assert_serde_names::<Hold>();
        assert_serde_names::<ModelKind>();
    }

    #[test]
    fn a_name_parses_exactly_or_ignoring_case_and_an_unknown_one_lists_the_names() {
        assert_eq!(ShapingKind::parse("tanh", false), Ok(ShapingKind::Tanh));
        assert_eq!(
            ShapingKind::parse("quad-exp", false),
            Ok(ShapingKind::QuadraticExp)
        );
        assert!(ShapingKind::parse("TANH", false).is_err());
        assert_eq!(ShapingKind::parse("TANH", true), Ok(ShapingKind::Tanh));
        let e = Hold::parse("soh", false).unwrap_err();
        assert_eq!(
            e.to_string(),
            "\"soh\" is no hold; possible values: zoh, foh"
        );
    }
}
