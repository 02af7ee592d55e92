//! What these tests read and run: the stand-in FMU binary, `hyst fmu`, the archive's entries and
//! the model description's elements.

use super::*;

/// A stand-in for libhyst_fmu.so: a 64-bit x86-64 ELF shared-object header followed by the
/// names of the FMI functions `hyst fmu` looks for.
pub(crate) fn fake_library(dir: &Path) -> PathBuf {
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
pub(crate) fn hyst_fmu(library: &Path, args: &[&str]) -> Output {
    HYST.command()
        .arg("fmu")
        .args(args)
        .env("HYST_FMU_LIBRARY", library)
        .output()
        .unwrap()
}

pub(crate) fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

pub(crate) fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "hyst fmu failed: {}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
}

/// The entries of a zip archive in order, with their contents.
pub(crate) fn unzip(path: &Path) -> Vec<(String, Vec<u8>, zip::CompressionMethod)> {
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

pub(crate) fn entry<'a>(
    entries: &'a [(String, Vec<u8>, zip::CompressionMethod)],
    name: &str,
) -> &'a [u8] {
    &entries
        .iter()
        .find(|(n, _, _)| n == name)
        .unwrap_or_else(|| panic!("no {name} in the FMU"))
        .1
}

/// The attributes of every `<tag ...>` element in `xml`, in document order (a minimal reader
/// for the XML hyst writes: double-quoted attributes, the five predefined entities).
pub(crate) fn elements(xml: &str, tag: &str) -> Vec<HashMap<String, String>> {
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

pub(crate) fn attr<'a>(element: &'a HashMap<String, String>, name: &str) -> &'a str {
    element
        .get(name)
        .unwrap_or_else(|| panic!("no attribute {name} in {element:?}"))
}

/// The names in `dir`, sorted.
pub(crate) fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

pub(crate) fn is_guid(s: &str) -> bool {
    let Some(inner) = s.strip_prefix('{').and_then(|s| s.strip_suffix('}')) else {
        return false;
    };
    let groups: Vec<&str> = inner.split('-').collect();
    groups.iter().map(|g| g.len()).collect::<Vec<_>>() == [8, 4, 4, 4, 12]
        && groups
            .iter()
            .all(|g| g.chars().all(|c| c.is_ascii_hexdigit()))
}

/// The variables of the model description `xml`, one line each: name, valueReference,
/// causality, variability, initial, start ("-" for an attribute that is not there).
pub(crate) fn variables(xml: &str) -> Vec<String> {
    let vars = elements(xml, "ScalarVariable");
    let reals = elements(xml, "Real");
    vars.iter()
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
        .collect()
}

/// The model description `xml` declares Co-Simulation only, with the capabilities the FMU has.
pub(crate) fn assert_co_simulation_only(xml: &str) {
    let cs = &elements(xml, "CoSimulation")[0];
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
    assert!(elements(xml, "ModelExchange").is_empty());
}

/// The operator FMU's unknowns: y (index 2) depends on x (1) as an output, and on x, k1 and k2
/// (1, 3, 4) as an initial unknown, the outputs listed first.
pub(crate) fn assert_operator_dependencies(xml: &str) {
    let unknowns = elements(xml, "Unknown");
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
}

/// `hyst fmu ARGS` fails, its message contains every one of `expected`, and `dir` holds exactly
/// `files` afterwards.
pub(crate) fn fails(dir: &Path, library: &Path, args: &[&str], expected: &[&str], files: &[&str]) {
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
