//! The named choices of the runtime and the fit ([`hyst_model::Choice`]: a shaping family, a k2
//! law, a form, a hold, …) as values of a command-line option: clap parses the names and
//! aliases of the choice's table, lists its names and descriptions in `--help`, and refuses any
//! other text with the possible names.

use std::ffi::OsStr;
use std::marker::PhantomData;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use hyst_model::Choice;

/// The value parser of an option whose value is a `C` ([`choice`]).
#[derive(Clone, Copy, Debug)]
pub struct ChoiceParser<C>(PhantomData<C>);

/// The value parser of an option whose value is a `C`, for `#[arg(value_parser = choice::<C>())]`.
#[must_use]
pub fn choice<C: Choice>() -> ChoiceParser<C> {
    ChoiceParser(PhantomData)
}

impl<C: Choice + Send + Sync> ChoiceParser<C> {
    fn values() -> impl Iterator<Item = PossibleValue> {
        C::CHOICES.iter().map(|(value, name, help)| {
            let aliases = C::ALIASES
                .iter()
                .filter(|(_, v)| v == value)
                .map(|(a, _)| *a);
            PossibleValue::new(*name).help(*help).aliases(aliases)
        })
    }
}

impl<C: Choice + Send + Sync> TypedValueParser for ChoiceParser<C> {
    type Value = C;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<C, clap::Error> {
        // clap's own parser of the names gives clap's own error (the option, the value, the
        // possible values); the table then maps the accepted text, a name or an alias.
        let text = PossibleValuesParser::new(Self::values()).parse_ref(cmd, arg, value)?;
        C::parse(&text, false)
            .map_err(|e| clap::Error::raw(clap::error::ErrorKind::InvalidValue, e).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(Self::values()))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use clap::Parser;
    use hyst_model::{Hold, ShapingKind};

    #[derive(Parser)]
    struct Args {
        #[arg(long, value_parser = choice::<ShapingKind>(), default_value = ShapingKind::Affine.name())]
        shaping: ShapingKind,
        #[arg(long, value_parser = choice::<Hold>())]
        hold: Option<Hold>,
    }

    #[test]
    fn names_and_aliases_parse_and_other_text_is_refused_with_the_names() {
        let a = Args::try_parse_from(["x", "--shaping", "quad-exp", "--hold", "zoh"]).unwrap();
        assert_eq!(a.shaping, ShapingKind::QuadraticExp);
        assert_eq!(a.hold, Some(Hold::Zoh));
        assert_eq!(
            Args::try_parse_from(["x"]).unwrap().shaping,
            ShapingKind::Affine
        );
        let e = Args::try_parse_from(["x", "--hold", "soh"])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("invalid value 'soh'") && e.contains("[possible values: zoh, foh]"),
            "{e}"
        );
    }
}
