//! `hyst fmu` end to end: the archive's listing, modelDescription.xml (FMI 2.0 co-simulation,
//! the variables, capabilities and model structure of docs/fmu.md), resources/fmu.toml, the model
//! file packed byte for byte, and bad arguments that name the problem and leave no file behind.
//!
//! The FMU binary here is a stand-in (an ELF header and the FMI symbol names): `hyst fmu` copies
//! it byte for byte, and scripts/test-fmu runs the real one through FMPy.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Output;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{piezo, piezo_fit};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// A stand-in for libhyst_fmu.so: a 64-bit x86-64 ELF shared-object header followed by the
/// names of the FMI functions `hyst fmu` looks for.
fn fake_library(dir: &Path) -> PathBuf {
    let mut b = vec![0u8; 64];
    b[..4].copy_from_slice(b"\x7fELF");
    b[4] = 2; // ELFCLASS64
    b[5] = 1; // little endian
    b[16] = 3; // ET_DYN
    b[18] = 62; // EM_X86_64
    for name in [
        "fmi2Instantiate",
        "fmi2DoStep",
        "fmi2GetReal",
        "fmi2SetReal",
        "fmi2GetFMUstate",
        "fmi2DeSerializeFMUstate",
    ] {
        b.push(0);
        b.extend_from_slice(name.as_bytes());
    }
    b.push(0);
    let path = dir.join("libhyst_fmu.so");
    std::fs::write(&path, b).unwrap();
    path
}

/// Runs `hyst fmu ARGS` with HYST_FMU_LIBRARY = `library`.
fn hyst_fmu(library: &Path, args: &[&str]) -> Output {
    HYST.command()
        .arg("fmu")
        .args(args)
        .env("HYST_FMU_LIBRARY", library)
        .output()
        .unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "hyst fmu failed: {}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
}

/// The entries of a zip archive in order, with their contents.
fn unzip(path: &Path) -> Vec<(String, Vec<u8>, zip::CompressionMethod)> {
    let mut archive = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    (0..archive.len())
        .map(|i| {
            let mut f = archive.by_index(i).unwrap();
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).unwrap();
            (f.name().unwrap().to_string(), bytes, f.compression())
        })
        .collect()
}

fn entry<'a>(entries: &'a [(String, Vec<u8>, zip::CompressionMethod)], name: &str) -> &'a [u8] {
    &entries
        .iter()
        .find(|(n, _, _)| n == name)
        .unwrap_or_else(|| panic!("no {name} in the FMU"))
        .1
}

/// The attributes of every `<tag ...>` element in `xml`, in document order (a minimal reader
/// for the XML hyst writes: double-quoted attributes, the five predefined entities).
fn elements(xml: &str, tag: &str) -> Vec<HashMap<String, String>> {
    let open = format!("<{tag}");
    let mut found = Vec::new();
    let mut rest = xml;
    while let Some(i) = rest.find(&open) {
        rest = &rest[i + open.len()..];
        if !rest.starts_with(|c: char| c.is_whitespace() || c == '/' || c == '>') {
            continue;
        }
        let end = rest.find('>').unwrap();
        let mut attrs = HashMap::new();
        let mut s = rest[..end].trim_end_matches('/');
        while let Some(eq) = s.find("=\"") {
            let key = s[..eq].trim().to_string();
            let after = &s[eq + 2..];
            let close = after.find('"').unwrap();
            let value = after[..close]
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&quot;", "\"")
                .replace("&apos;", "'")
                .replace("&amp;", "&");
            attrs.insert(key, value);
            s = &after[close + 1..];
        }
        found.push(attrs);
    }
    found
}

fn attr<'a>(element: &'a HashMap<String, String>, name: &str) -> &'a str {
    element
        .get(name)
        .unwrap_or_else(|| panic!("no attribute {name} in {element:?}"))
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn is_guid(s: &str) -> bool {
    let Some(inner) = s.strip_prefix('{').and_then(|s| s.strip_suffix('}')) else {
        return false;
    };
    let groups: Vec<&str> = inner.split('-').collect();
    groups.iter().map(|g| g.len()).collect::<Vec<_>>() == [8, 4, 4, 4, 12]
        && groups
            .iter()
            .all(|g| g.chars().all(|c| c.is_ascii_hexdigit()))
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

    let cs = &elements(&xml, "CoSimulation")[0];
    for (key, value) in [
        ("modelIdentifier", "hyst"),
        ("canHandleVariableCommunicationStepSize", "true"),
        ("canGetAndSetFMUstate", "true"),
        ("canSerializeFMUstate", "true"),
        ("canInterpolateInputs", "false"),
        ("maxOutputDerivativeOrder", "0"),
        ("canRunAsynchronuously", "false"),
        ("canBeInstantiatedOnlyOncePerProcess", "false"),
        ("canNotUseMemoryManagementFunctions", "true"),
        ("providesDirectionalDerivative", "false"),
    ] {
        assert_eq!(attr(cs, key), value, "CoSimulation {key}");
    }
    assert!(elements(&xml, "ModelExchange").is_empty());
    assert!(elements(&xml, "UnitDefinitions").is_empty());

    let vars = elements(&xml, "ScalarVariable");
    let reals = elements(&xml, "Real");
    // name, valueReference, causality, variability, initial, start.
    let summary: Vec<String> = vars
        .iter()
        .zip(&reals)
        .map(|(v, r)| {
            let or_none = |s: Option<&String>| s.cloned().unwrap_or_else(|| "-".into());
            format!(
                "{} {} {} {} {} {}",
                attr(v, "name"),
                attr(v, "valueReference"),
                attr(v, "causality"),
                attr(v, "variability"),
                or_none(v.get("initial")),
                or_none(r.get("start")),
            )
        })
        .collect();
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

    let unknowns = elements(&xml, "Unknown");
    assert_eq!(unknowns.len(), 2);
    let outputs = xml.find("<Outputs>").unwrap();
    let initial = xml.find("<InitialUnknowns>").unwrap();
    assert!(outputs < initial);
    assert_eq!(attr(&unknowns[0], "index"), "2");
    assert_eq!(attr(&unknowns[0], "dependencies"), "1");
    assert_eq!(attr(&unknowns[0], "dependenciesKind"), "dependent");
    assert_eq!(attr(&unknowns[1], "index"), "2");
    assert_eq!(attr(&unknowns[1], "dependencies"), "1 3 4");
    assert_eq!(
        attr(&unknowns[1], "dependenciesKind"),
        "dependent dependent dependent"
    );

    let config: toml::Table = text(entry(&entries, "resources/fmu.toml")).parse().unwrap();
    assert_eq!(config["format"].as_str(), Some("hyst-fmu"));
    assert_eq!(config["version"].as_integer(), Some(1));
    assert_eq!(config["guid"].as_str(), Some(guid));
    assert_eq!(config["kind"].as_str(), Some("operator"));
    assert_eq!(config["inverse"].as_bool(), Some(false));
    assert_eq!(config["k1"].as_float(), Some(0.2));
    assert_eq!(config["k2"].as_float(), Some(8.0));

    let html = text(entry(&entries, "documentation/index.html"));
    assert!(html.contains("<title>backlash"), "{html}");
    assert!(html.contains("FMI 2.0 Co-Simulation"), "{html}");
    assert!(
        html.contains("hyst fmu --k1 0.2 --k2 8 -o"),
        "the command that made the FMU: {html}"
    );
    for v in ["x", "y", "k1", "k2"] {
        assert!(html.contains(&format!("<code>{v}</code>")), "{v}: {html}");
    }

    // Nothing else was written, and a second FMU gets a fresh GUID.
    assert_eq!(listing(dir.path()), ["backlash.fmu", "libhyst_fmu.so"]);
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

/// Fits the bundled piezo data into `dir/piezo.toml` (the debug build takes about a second).
fn fit_piezo(dir: &Path) -> PathBuf {
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

    // Empty units (as hyst fit writes them): no unit attributes, no UnitDefinitions.
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

/// `hyst fmu ARGS` fails, its message contains every one of `expected`, and `dir` holds exactly
/// `files` afterwards.
fn fails(dir: &Path, library: &Path, args: &[&str], expected: &[&str], files: &[&str]) {
    let out = hyst_fmu(library, args);
    let err = text(&out.stderr);
    assert!(!out.status.success(), "hyst fmu {args:?} succeeded");
    for e in expected {
        assert!(
            err.contains(e),
            "hyst fmu {args:?}: expected {e:?} in {err:?}"
        );
    }
    assert_eq!(listing(dir), files, "hyst fmu {args:?}");
}

#[test]
fn bad_arguments_name_the_problem_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = fake_library(d);
    let fmu = d.join("out.fmu");
    let fmu = fmu.to_str().unwrap();
    let only_lib = ["libhyst_fmu.so"];

    fails(
        d,
        &lib,
        &["--k1", "-1", "--k2", "8", "-o", fmu],
        &["k1 = -1", "must be finite and > 0"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "inf", "-o", fmu],
        &["k2 = inf"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "NaN", "-o", fmu],
        &["k2 = NaN"],
        &only_lib,
    );
    fails(d, &lib, &["--k1", "0.2", "-o", fmu], &["--k2"], &only_lib);
    let missing = d.join("missing.toml");
    fails(
        d,
        &lib,
        &["--model", missing.to_str().unwrap(), "-o", fmu],
        &[missing.to_str().unwrap(), "cannot read"],
        &only_lib,
    );
    let not_a_model = d.join("notes.toml");
    std::fs::write(&not_a_model, "title = \"not a model\"\n").unwrap();
    fails(
        d,
        &lib,
        &["--model", not_a_model.to_str().unwrap(), "-o", fmu],
        &["notes.toml", "not a hyst model file"],
        &["libhyst_fmu.so", "notes.toml"],
    );
    std::fs::remove_file(&not_a_model).unwrap();
    fails(
        d,
        &lib,
        &[
            "--model",
            missing.to_str().unwrap(),
            "--k1",
            "0.2",
            "-o",
            fmu,
        ],
        &["--model", "cannot be used with", "--k1"],
        &only_lib,
    );
    let csv = d.join("out.csv");
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "8", "-o", csv.to_str().unwrap()],
        &["out.csv", "NAME.fmu"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &[
            "--k1",
            "0.2",
            "--k2",
            "8",
            "-o",
            d.join("no-dir/out.fmu").to_str().unwrap(),
        ],
        &["no-dir/out.fmu", "No such file or directory"],
        &only_lib,
    );

    // The binary: missing (the message says how to build it), or not a shared library.
    let nowhere = d.join("nowhere/libhyst_fmu.so");
    fails(
        d,
        &nowhere,
        &["--k1", "0.2", "--k2", "8", "-o", fmu],
        &[
            nowhere.to_str().unwrap(),
            "HYST_FMU_LIBRARY",
            "cargo build -p hyst-fmu",
        ],
        &only_lib,
    );
    let script = d.join("script.so");
    std::fs::write(&script, "#!/bin/sh\n").unwrap();
    fails(
        d,
        &script,
        &["--k1", "0.2", "--k2", "8", "-o", fmu],
        &["script.so", "not an ELF file", "cargo build -p hyst-fmu"],
        &["libhyst_fmu.so", "script.so"],
    );
    std::fs::remove_file(&script).unwrap();

    // A model file that happens to be called *.fmu is never overwritten by its own FMU.
    let fitted = fit_piezo(d);
    let odd = d.join("model.fmu");
    std::fs::rename(&fitted, &odd).unwrap();
    let before = std::fs::read(&odd).unwrap();
    fails(
        d,
        &lib,
        &[
            "--model",
            odd.to_str().unwrap(),
            "-o",
            odd.to_str().unwrap(),
        ],
        &["model.fmu", "the model file itself"],
        &["libhyst_fmu.so", "model.fmu"],
    );
    assert_eq!(std::fs::read(&odd).unwrap(), before);

    // A failed run keeps an existing FMU as it was.
    ok(&hyst_fmu(&lib, &["--k1", "0.2", "--k2", "8", "-o", fmu]));
    let good = std::fs::read(fmu).unwrap();
    fails(
        d,
        &lib,
        &["--k1", "0", "--k2", "8", "-o", fmu],
        &["k1 = 0"],
        &["libhyst_fmu.so", "model.fmu", "out.fmu"],
    );
    assert_eq!(std::fs::read(fmu).unwrap(), good);
}

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
