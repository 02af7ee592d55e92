//! The FMU of an operator: the layout and model description of the FMI 2.0 standard, a fresh
//! GUID for each FMU.

use crate::archive::*;

/// The FMU's documentation page `html` names the FMU, the standard, the command that made it
/// and every variable.
fn assert_documents_the_operator(html: &str) {
    assert!(html.contains("<title>backlash"), "{html}");
    assert!(html.contains("FMI 2.0 Co-Simulation"), "{html}");
    assert!(
        html.contains("hyst fmu --k1 0.2 --k2 8 -o"),
        "the command that made the FMU: {html}"
    );
    for v in ["x", "y", "k1", "k2"] {
        assert!(html.contains(&format!("<code>{v}</code>")), "{v}: {html}");
    }
}

#[test]
fn operator_fmu_has_the_layout_and_model_description_of_the_spec() {
    let dir = tempfile::tempdir().unwrap();
    let lib = fake_library(dir.path());
    let fmu = dir.path().join("backlash.fmu");
    let out = hyst_fmu(
        &lib,
        &["--k1", "0.2", "--k2", "8", "-o", fmu.to_str().unwrap()],
    );
    ok(&out);
    assert!(
        text(&out.stdout).contains("backlash.fmu"),
        "{}",
        text(&out.stdout)
    );

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
            "documentation/",
            "documentation/index.html",
        ]
    );
    assert_eq!(
        entry(&entries, "binaries/linux64/hyst.so"),
        std::fs::read(&lib).unwrap()
    );
    for (name, _, method) in &entries {
        if !name.ends_with('/') {
            assert_eq!(*method, zip::CompressionMethod::Deflated, "{name}");
        }
    }

    let xml = text(entry(&entries, "modelDescription.xml"));
    assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"));
    let md = &elements(&xml, "fmiModelDescription")[0];
    assert_eq!(attr(md, "fmiVersion"), "2.0");
    assert_eq!(attr(md, "modelName"), "backlash");
    assert_eq!(
        attr(md, "generationTool"),
        format!("hyst {}", env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(attr(md, "variableNamingConvention"), "flat");
    let when = attr(md, "generationDateAndTime");
    assert!(
        when.len() == 20 && when.ends_with('Z') && &when[10..11] == "T",
        "{when}"
    );
    let guid = attr(md, "guid");
    assert!(is_guid(guid), "{guid}");

    assert_co_simulation_only(&xml);
    assert!(elements(&xml, "UnitDefinitions").is_empty());

    let vars = elements(&xml, "ScalarVariable");
    let reals = elements(&xml, "Real");
    let summary = variables(&xml);
    assert_eq!(
        summary,
        [
            "x 0 input continuous - 0.0",
            "y 1 output continuous calculated -",
            "k1 2 parameter fixed exact 0.2",
            "k2 3 parameter fixed exact 8.0",
        ]
    );
    assert!(vars.iter().all(|v| !attr(v, "description").is_empty()));
    assert!(reals.iter().all(|r| !r.contains_key("unit")));

    assert_operator_dependencies(&xml);

    let config: toml::Table = text(entry(&entries, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["format"].as_str(), Some("hyst-fmu"));
    assert_eq!(config["version"].as_integer(), Some(1));
    assert_eq!(config["guid"].as_str(), Some(guid));
    assert_eq!(config["kind"].as_str(), Some("operator"));
    assert_eq!(config["inverse"].as_bool(), Some(false));
    assert_eq!(config["k1"].as_float(), Some(0.2));
    assert_eq!(config["k2"].as_float(), Some(8.0));

    assert_documents_the_operator(&text(entry(&entries, "documentation/index.html")));

    // Nothing else was written.
    assert_eq!(listing(dir.path()), ["backlash.fmu", "libhyst_fmu.so"]);
}

/// A second FMU of the same name gets a fresh GUID and its own parameters (here an inverse),
/// and replaces the first; nothing else is written.
#[test]
fn a_second_fmu_gets_a_fresh_guid_and_its_own_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let lib = fake_library(dir.path());
    let fmu = dir.path().join("backlash.fmu");
    ok(&hyst_fmu(
        &lib,
        &["--k1", "0.2", "--k2", "8", "-o", fmu.to_str().unwrap()],
    ));
    let first = unzip(&fmu);
    let xml = text(entry(&first, "modelDescription.xml"));
    let guid = attr(&elements(&xml, "fmiModelDescription")[0], "guid").to_string();
    ok(&hyst_fmu(
        &lib,
        &[
            "--k1",
            "1e-7",
            "--k2",
            "3e5",
            "--inverse",
            "-o",
            fmu.to_str().unwrap(),
        ],
    ));
    let again = unzip(&fmu);
    let xml2 = text(entry(&again, "modelDescription.xml"));
    let guid2 = attr(&elements(&xml2, "fmiModelDescription")[0], "guid").to_string();
    assert!(is_guid(&guid2) && guid2 != guid, "{guid2} vs {guid}");
    let config: toml::Table = text(entry(&again, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["guid"].as_str(), Some(guid2.as_str()));
    assert_eq!(config["inverse"].as_bool(), Some(true));
    assert_eq!(config["k1"].as_float(), Some(1e-7));
    assert_eq!(config["k2"].as_float(), Some(3e5));
    let starts: Vec<f64> = elements(&xml2, "Real")
        .iter()
        .filter_map(|r| r.get("start").map(|s| s.parse().unwrap()))
        .collect();
    assert_eq!(starts, [0.0, 1e-7, 3e5]);
    assert_eq!(listing(dir.path()), ["backlash.fmu", "libhyst_fmu.so"]);
}
