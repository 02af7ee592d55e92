//! What a model FMU's configuration carries: saturation for the inverse of a saturating model,
//! the timing of a timed model.

use super::*;
use crate::archive::*;
use crate::model::*;

#[test]
fn saturate_is_written_for_the_inverse_of_a_saturating_model_only() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = fake_library(d);
    let affine = fit_piezo(d);
    let tanh = d.join("tanh.toml");
    let data = piezo();
    let out = HYST
        .command()
        .args(["fit", data.to_str().unwrap(), "--input", "u_actuator_V"])
        .args([
            "--output",
            "y_capsensor_um",
            "--output-shaping",
            "tanh",
            "-o",
        ])
        .arg(&tanh)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let fmu = d.join("comp.fmu");
    let (fmu_s, tanh_s, affine_s) = (
        fmu.to_str().unwrap(),
        tanh.to_str().unwrap(),
        affine.to_str().unwrap(),
    );
    let before = ["libhyst_fmu.so", "piezo.toml", "tanh.toml"];
    fails(
        d,
        &lib,
        &[
            "--k1",
            "0.2",
            "--k2",
            "8",
            "--inverse",
            "--saturate",
            "-o",
            fmu_s,
        ],
        &["--saturate applies to --model FILE --inverse"],
        &before,
    );
    fails(
        d,
        &lib,
        &["--model", tanh_s, "--saturate", "-o", fmu_s],
        &["--saturate applies to --model FILE --inverse"],
        &before,
    );
    fails(
        d,
        &lib,
        &["--model", affine_s, "--inverse", "--saturate", "-o", fmu_s],
        &["--saturate", "unbounded"],
        &before,
    );
    let out = hyst_fmu(
        &lib,
        &["--model", tanh_s, "--inverse", "--saturate", "-o", fmu_s],
    );
    ok(&out);
    assert!(text(&out.stdout).contains("desired outputs clamped into ["));
    let entries = unzip(&fmu);
    let config: toml::Table = text(entry(&entries, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["saturate"].as_bool(), Some(true));
    // Without --saturate the key is absent (the FMU refuses values beyond the range).
    ok(&hyst_fmu(
        &lib,
        &["--model", tanh_s, "--inverse", "-o", fmu_s],
    ));
    let config: toml::Table = text(entry(&unzip(&fmu), "resources/fmu.toml"))
        .parse()
        .unwrap();
    assert!(!config.contains_key("saturate"));
}

/// A model with dynamics or a rate term is packed for what the FMU runs (the direct model at
/// each communication step's length, the compensator with the derivative inputs x_d1 …),
/// and what it cannot run (the inverse of a model with a rate term, --saturate) is refused with
/// the reason, leaving no file.
#[test]
fn timed_models_are_packed_with_their_timing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = fake_library(d);
    let fitted = std::fs::read_to_string(fit_piezo(d)).unwrap();
    let timed = |name: &str, sections: &str| {
        let version = fitted
            .lines()
            .find(|l| l.starts_with("version = "))
            .unwrap();
        let text = fitted.replacen(version, "version = 4", 1) + "\n" + sections;
        let path = d.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let dynamics = timed("dynamics.toml", "[dynamics]\nb = 1.0\na = [0.05, 0.001]\n");
    let rate = timed("rate.toml", "[rate]\nc = 0.3\n");
    let capabilities = |xml: &str| {
        let cs = &elements(xml, "CoSimulation")[0];
        [
            attr(cs, "canHandleVariableCommunicationStepSize").to_string(),
            attr(cs, "canSerializeFMUstate").to_string(),
        ]
    };
    let fmu = d.join("timed.fmu");
    let fmu = fmu.to_str().unwrap();
    for model in [&dynamics, &rate] {
        ok(&hyst_fmu(&lib, &["--model", model, "-o", fmu]));
        let entries = unzip(Path::new(fmu));
        let xml = text(entry(&entries, "modelDescription.xml"));
        assert_eq!(capabilities(&xml), ["true", "false"], "{model}");
        let names: Vec<String> = elements(&xml, "ScalarVariable")
            .iter()
            .map(|v| attr(v, "name").to_string())
            .collect();
        assert_eq!(names, ["x", "y"]);
        let html = text(entry(&entries, "documentation/index.html"));
        assert!(html.contains("time step to the next sample"), "{html}");
    }

    ok(&hyst_fmu(
        &lib,
        &["--model", &dynamics, "--inverse", "-o", fmu],
    ));
    let entries = unzip(Path::new(fmu));
    let xml = text(entry(&entries, "modelDescription.xml"));
    assert_eq!(capabilities(&xml), ["true", "false"]);
    let md = &elements(&xml, "fmiModelDescription")[0];
    assert!(
        attr(md, "description").contains("Lemma 5.1's compensator"),
        "{xml}"
    );
    let vars = elements(&xml, "ScalarVariable");
    let summary: Vec<String> = vars
        .iter()
        .map(|v| {
            format!(
                "{} {} {}",
                attr(v, "name"),
                attr(v, "valueReference"),
                attr(v, "causality")
            )
        })
        .collect();
    assert_eq!(
        summary,
        ["x 0 input", "y 1 output", "x_d1 2 input", "x_d2 3 input"]
    );
    let x_d2 = attr(&vars[3], "description");
    assert!(x_d2.contains("y_capsensor_um_d2"), "{x_d2}");
    let unknowns = elements(&xml, "Unknown");
    assert_eq!(attr(&unknowns[0], "dependencies"), "1 3 4");
    assert_eq!(
        attr(&unknowns[0], "dependenciesKind"),
        "dependent dependent dependent"
    );
    assert_eq!(attr(&unknowns[1], "dependencies"), "1 3 4");
    assert_eq!(
        entry(&entries, "resources/model.toml"),
        std::fs::read(&dynamics).unwrap()
    );
    std::fs::remove_file(fmu).unwrap();

    let files = ["dynamics.toml", "libhyst_fmu.so", "piezo.toml", "rate.toml"];
    fails(
        d,
        &lib,
        &["--model", &rate, "--inverse", "-o", fmu],
        &["rate.toml", "the inverse of a model with a rate term"],
        &files,
    );
    fails(
        d,
        &lib,
        &["--model", &dynamics, "--inverse", "--saturate", "-o", fmu],
        &["dynamics.toml", "--saturate", "dynamics of order 2"],
        &files,
    );
}
