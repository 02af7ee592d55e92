//! The FMU of a model file: the file packed byte for byte, its columns and units named.

use super::*;
use crate::archive::*;

/// Fits the bundled piezo data into `dir/piezo.toml` (the debug build takes about a second).
pub(crate) fn fit_piezo(dir: &Path) -> PathBuf {
    let model = dir.join("piezo.toml");
    let data = piezo();
    let out = HYST
        .command()
        .args(piezo_fit(&data, &model))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    model
}

#[test]
fn model_fmu_packs_the_model_file_and_names_its_columns_and_units() {
    let dir = tempfile::tempdir().unwrap();
    let lib = fake_library(dir.path());
    let fitted = fit_piezo(dir.path());
    // Units (which hyst fit leaves empty) with characters XML must escape.
    let model_text = std::fs::read_to_string(&fitted)
        .unwrap()
        .replace("[units]\ninput = \"\"", "[units]\ninput = \"V\"")
        .replace("output = \"\"\n", "output = \"µm & <rel>\"\n");
    assert!(model_text.contains("input = \"V\"") && model_text.contains("<rel>"));
    let model = dir.path().join("units.toml");
    std::fs::write(&model, &model_text).unwrap();

    let fmu = dir.path().join("piezo inverse.fmu");
    ok(&hyst_fmu(
        &lib,
        &[
            "--model",
            model.to_str().unwrap(),
            "--inverse",
            "-o",
            fmu.to_str().unwrap(),
        ],
    ));
    let entries = unzip(&fmu);
    let names: Vec<&str> = entries.iter().map(|(n, _, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "modelDescription.xml",
            "binaries/",
            "binaries/linux64/",
            "binaries/linux64/hyst.so",
            "resources/",
            "resources/fmu.toml",
            "resources/model.toml",
            "documentation/",
            "documentation/index.html",
        ]
    );
    assert_eq!(
        entry(&entries, "resources/model.toml"),
        model_text.as_bytes()
    );

    let xml = text(entry(&entries, "modelDescription.xml"));
    let md = &elements(&xml, "fmiModelDescription")[0];
    assert_eq!(attr(md, "modelName"), "piezo inverse");
    let units: Vec<String> = elements(&xml, "Unit")
        .iter()
        .map(|u| attr(u, "name").to_string())
        .collect();
    // The inverse's input is the model's output (a desired displacement), its output the
    // model's input (a voltage).
    assert_eq!(units, ["µm & <rel>", "V"]);
    let vars = elements(&xml, "ScalarVariable");
    assert_eq!(
        vars.iter().map(|v| attr(v, "name")).collect::<Vec<_>>(),
        ["x", "y"]
    );
    let x = attr(&vars[0], "description");
    let y = attr(&vars[1], "description");
    assert!(
        x.contains("y_capsensor_um") && x.contains("[µm & <rel>]"),
        "{x}"
    );
    assert!(y.contains("u_actuator_V") && y.contains("[V]"), "{y}");
    let reals = elements(&xml, "Real");
    assert_eq!(attr(&reals[0], "unit"), "µm & <rel>");
    assert_eq!(attr(&reals[1], "unit"), "V");
    let unknowns = elements(&xml, "Unknown");
    assert_eq!(attr(&unknowns[1], "dependencies"), "1");

    let config: toml::Table = text(entry(&entries, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["kind"].as_str(), Some("model"));
    assert_eq!(config["inverse"].as_bool(), Some(true));
    assert_eq!(config["guid"].as_str(), Some(attr(md, "guid")));
    assert!(!config.contains_key("k1") && !config.contains_key("k2"));
}

/// A model FMU of a model with empty units (as hyst fit writes them): no unit attributes, no
/// UnitDefinitions, the model file packed as it is.
#[test]
fn a_model_fmu_of_empty_units_has_no_unit_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let lib = fake_library(dir.path());
    let fitted = fit_piezo(dir.path());
    let direct = dir.path().join("piezo.fmu");
    ok(&hyst_fmu(
        &lib,
        &[
            "--model",
            fitted.to_str().unwrap(),
            "-o",
            direct.to_str().unwrap(),
        ],
    ));
    let entries = unzip(&direct);
    let xml = text(entry(&entries, "modelDescription.xml"));
    assert!(
        !xml.contains("UnitDefinitions") && !xml.contains("unit="),
        "{xml}"
    );
    let vars = elements(&xml, "ScalarVariable");
    assert!(attr(&vars[0], "description").contains("u_actuator_V"));
    let config: toml::Table = text(entry(&entries, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["inverse"].as_bool(), Some(false));
    assert_eq!(
        entry(&entries, "resources/model.toml"),
        std::fs::read(&fitted).unwrap()
    );
}
