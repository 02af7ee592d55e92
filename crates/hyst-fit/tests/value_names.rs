//! With the `clap` feature, the command-line names of hyst-fit's choices are fixed: they are
//! the CLI's contract (`hyst fit --k2 affine`, …) and, where the enum is also serialized, the
//! model file's names.
#![cfg(feature = "clap")]

use clap::ValueEnum;
use hyst_fit::modelfile::ModelKind;
use hyst_fit::pi::PiOutputKind;
use hyst_fit::{InitialState, K2Kind, ShapingKind};

/// The command-line names of every variant, in the order `--help` lists them.
fn names<E: ValueEnum>() -> Vec<String> {
    E::value_variants()
        .iter()
        .filter_map(|v| v.to_possible_value())
        .map(|p| p.get_name().to_string())
        .collect()
}

/// The model file's (serde's) name of a value.
fn serde_name<E: serde::Serialize>(value: &E) -> String {
    toml::Value::try_from(value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

#[test]
fn command_line_names_are_the_contract() {
    assert_eq!(
        names::<ShapingKind>(),
        ["affine", "poly2", "poly3", "tanh", "langevin", "quad-exp"]
    );
    assert_eq!(names::<K2Kind>(), ["constant", "affine"]);
    assert_eq!(names::<InitialState>(), ["rising", "falling", "line"]);
    assert_eq!(names::<PiOutputKind>(), ["none", "poly2", "poly3"]);
    assert_eq!(names::<ModelKind>(), ["smooth", "pi"]);
}

#[test]
fn command_line_and_model_file_agree() {
    for (name, kind) in ShapingKind::ALL {
        assert_eq!(kind.name(), name);
        assert_eq!(serde_name(&kind), name);
        assert_eq!(ShapingKind::from_str(name, false), Ok(kind));
    }
    for k in K2Kind::value_variants() {
        assert_eq!(
            Some(serde_name(k)),
            k.to_possible_value().map(|p| p.get_name().into())
        );
    }
    for s in InitialState::value_variants() {
        assert_eq!(
            Some(serde_name(s)),
            s.to_possible_value().map(|p| p.get_name().into())
        );
    }
    // The one deliberate difference: the file says what the CLI abbreviates.
    assert_eq!(
        serde_name(&ModelKind::PrandtlIshlinskii),
        "prandtl-ishlinskii"
    );
    assert_eq!(
        ModelKind::from_str("pi", false),
        Ok(ModelKind::PrandtlIshlinskii)
    );
}
