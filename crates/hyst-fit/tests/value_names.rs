//! The names of the choices are fixed: they are the CLI's and Python's contract (`hyst fit
//! --k2 affine`, `hyst.fit(k2="affine")`) and, where the value is also serialized, the model
//! file's names.

use hyst_fit::pi_fit::PiOutputKind;
use hyst_fit::{FormChoice, StartChoice};
use hyst_model::{Choice, Form, Hold, InitialState, K2Kind, ModelKind, RateTerm, ShapingKind};

/// The names of every value, in the order `--help` lists them.
fn names<C: Choice>() -> Vec<&'static str> {
    C::CHOICES.iter().map(|(_, n, _)| *n).collect()
}

/// The model file's (serde's) name of a value.
fn serde_name<E: serde::Serialize>(value: &E) -> String {
    toml::Value::try_from(value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// Every value's name is serde's, and parses back to it.
fn file_and_command_line_agree<C: Choice + serde::Serialize + std::fmt::Debug>() {
    for (value, name, _) in C::CHOICES {
        assert_eq!(serde_name(value), *name, "{value:?}");
        assert_eq!(value.name(), *name);
        assert_eq!(C::parse(name, false), Ok(*value));
    }
}

#[test]
fn command_line_names_are_the_contract() {
    assert_eq!(
        names::<ShapingKind>(),
        [
            "affine",
            "poly2",
            "poly3",
            "tanh",
            "langevin",
            "quadratic-exp"
        ]
    );
    assert_eq!(names::<K2Kind>(), ["constant", "affine"]);
    assert_eq!(names::<Form>(), ["operator", "stop"]);
    assert_eq!(names::<Hold>(), ["zoh", "foh"]);
    assert_eq!(names::<RateTerm>(), ["viscous"]);
    assert_eq!(names::<FormChoice>(), ["auto", "operator", "stop"]);
    assert_eq!(
        names::<StartChoice>(),
        ["auto", "rising", "falling", "line"]
    );
    // The start rule is the core's: its names are the model file's.
    let starts = [
        InitialState::Rising,
        InitialState::Falling,
        InitialState::Line,
    ];
    assert_eq!(
        starts.map(|s| serde_name(&s)),
        ["rising", "falling", "line"]
    );
    assert_eq!(names::<PiOutputKind>(), ["none", "poly2", "poly3"]);
    assert_eq!(names::<ModelKind>(), ["smooth", "prandtl-ishlinskii"]);
}

#[test]
fn command_line_and_model_file_agree() {
    file_and_command_line_agree::<ShapingKind>();
    file_and_command_line_agree::<K2Kind>();
    file_and_command_line_agree::<Form>();
    file_and_command_line_agree::<Hold>();
    file_and_command_line_agree::<RateTerm>();
    file_and_command_line_agree::<FormChoice>();
    file_and_command_line_agree::<StartChoice>();
    file_and_command_line_agree::<ModelKind>();
    // The command line also takes the short `pi`.
    assert_eq!(
        ModelKind::parse("pi", false),
        Ok(ModelKind::PrandtlIshlinskii)
    );
}

#[test]
fn the_old_spelling_of_quadratic_exp_still_reads() {
    // Model files and scripts of earlier versions wrote `quad-exp` (docs/formats.md).
    assert_eq!(
        ShapingKind::parse("quad-exp", false),
        Ok(ShapingKind::QuadraticExp)
    );
    let old: toml::Table = toml::from_str("s = \"quad-exp\"").unwrap_or_default();
    let kind: Result<ShapingKind, _> = old["s"].clone().try_into();
    assert_eq!(kind.ok(), Some(ShapingKind::QuadraticExp));
    // New files write the one spelling.
    assert_eq!(serde_name(&ShapingKind::QuadraticExp), "quadratic-exp");
}
