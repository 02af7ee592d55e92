//! Old spellings of flags. Each flag has one meaning on every subcommand: `-o`/`--out` is the
//! file (or directory) a command writes, `--input` and `--output` name the data's columns. The
//! spellings a subcommand had before are still accepted (clap aliases of the new flag); this
//! module finds those a command line uses, for a note on standard error.

use std::ffi::OsString;

/// A flag's old spelling on one subcommand and the flag it now is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OldSpelling {
    /// The subcommand (`run`, `fit`, …).
    pub command: &'static str,
    /// The old spelling, with its dashes.
    pub old: &'static str,
    /// The flag it is now.
    pub new: &'static str,
}

/// Every old spelling still accepted.
pub const OLD_SPELLINGS: &[OldSpelling] = &[
    OldSpelling {
        command: "run",
        old: "--output",
        new: "-o/--out",
    },
    OldSpelling {
        command: "export",
        old: "--output",
        new: "-o/--out",
    },
    OldSpelling {
        command: "fmu",
        old: "--output",
        new: "-o/--out",
    },
    OldSpelling {
        command: "fit",
        old: "--model-out",
        new: "-o/--out",
    },
    OldSpelling {
        command: "fit",
        old: "--operators",
        new: "--plays",
    },
    OldSpelling {
        command: "adapt",
        old: "--output-file",
        new: "-o/--out",
    },
];

/// The old spellings a command line (`args` without the program's name) uses, each once, in
/// the order of [`OLD_SPELLINGS`]. The subcommand is the first argument; flags are looked for
/// up to `--` (after it every argument is a value), as `--flag` or `--flag=VALUE`.
pub fn used(args: &[OsString]) -> Vec<OldSpelling> {
    let Some(command) = args.first().and_then(|a| a.to_str()) else {
        return Vec::new();
    };
    let flags: Vec<&str> = args[1..]
        .iter()
        .filter_map(|a| a.to_str())
        .take_while(|a| *a != "--")
        .map(|a| a.split_once('=').map_or(a, |(flag, _)| flag))
        .collect();
    OLD_SPELLINGS
        .iter()
        .filter(|s| s.command == command && flags.contains(&s.old))
        .copied()
        .collect()
}

/// The note for one old spelling.
pub fn note(spelling: &OldSpelling) -> String {
    format!(
        "note: `hyst {} {}` is the old spelling of {}; it still works. Every subcommand writes \
         its output to -o/--out, and --input/--output name columns",
        spelling.command, spelling.old, spelling.new
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Vec<OsString> {
        list.iter().map(OsString::from).collect()
    }

    #[test]
    fn finds_the_old_spellings_of_the_subcommand_only() {
        let found = used(&args(&[
            "fit",
            "d.csv",
            "--input",
            "x",
            "--output",
            "y",
            "--model-out",
            "m.toml",
        ]));
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].old, "--model-out");
        // `--output` is a column of fit, not an old spelling there.
        assert!(used(&args(&["fit", "d.csv", "--output", "y", "-o", "m.toml"])).is_empty());
        let found = used(&args(&["run", "d.csv", "--output=o.csv"]));
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].new, "-o/--out");
    }

    #[test]
    fn values_after_a_double_dash_are_not_flags() {
        assert!(used(&args(&["run", "--", "--output"])).is_empty());
        assert!(used(&args(&[])).is_empty());
    }
}
