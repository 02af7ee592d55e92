//! With the `clap` feature, the command-line names of hyst-fit's choices are fixed: they are
//! the CLI's contract (`hyst fit --k2 affine`, …) and, where the enum is also serialized, the
//! model file's names.
#![cfg(feature = "clap")]

use clap::ValueEnum;
use hyst_fit::pi_fit::PiOutputKind;
use hyst_model::ModelKind;
use hyst_model::{InitialState, K2Kind, ShapingKind};

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
    // The start rule is the core's (no clap there): its names are the model file's.
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
    // The file and the command line say the same; the command line also takes the short `pi`.
    assert_eq!(
        serde_name(&ModelKind::PrandtlIshlinskii),
        "prandtl-ishlinskii"
    );
    for name in ["prandtl-ishlinskii", "pi"] {
        assert_eq!(
            ModelKind::from_str(name, false),
            Ok(ModelKind::PrandtlIshlinskii)
        );
    }
}

#[test]
fn the_old_spelling_of_quadratic_exp_still_reads() {
    // Model files and scripts of earlier versions wrote `quad-exp` (docs/formats.md).
    assert_eq!(
        ShapingKind::from_str("quad-exp", false),
        Ok(ShapingKind::QuadraticExp)
    );
    let old: toml::Table = toml::from_str("s = \"quad-exp\"").unwrap_or_default();
    let kind: Result<ShapingKind, _> = old["s"].clone().try_into();
    assert_eq!(kind.ok(), Some(ShapingKind::QuadraticExp));
    // New files write the one spelling.
    assert_eq!(serde_name(&ShapingKind::QuadraticExp), "quadratic-exp");
}
