//! The header of `hyst run`'s OUTPUT (docs/formats.md, "hyst run"): every column of INPUT
//! first, unchanged and under its own name, then the columns the run computes, named after what
//! they are: a model's output column for the model, its input column (the command) for its
//! inverse, `y` for `--k1/--k2`.

use std::collections::HashSet;

use anyhow::{bail, Result};

/// What one run computes, for the names of its columns.
pub struct Computed<'a> {
    /// The name of the one computed signal: the model's output column (direct), its input
    /// column (`--inverse`: the command), or `y` (`--k1/--k2`, either direction).
    pub base: &'a str,
    /// The input columns run, one operator each.
    pub columns: &'a [&'a str],
    /// Time derivatives carried (`--derivatives N`).
    pub derivatives: usize,
    /// A column per input column with a suffix and what it holds, after the outputs and their
    /// derivatives (`_saturated`: the desired output after `--saturate`; `_filtered`: the
    /// prefiltered reference).
    pub extra: Option<&'a str>,
}

/// The suffix that makes a computed column's name differ from a column of INPUT with the same
/// name (repeated until it does).
pub const CLASH_SUFFIX: &str = "_out";

/// The names of OUTPUT: `input` (INPUT's columns), then for one input column `c`: `BASE`,
/// `BASE_d1 … BASE_dN`, `c_EXTRA`; for several: `BASE_c` for each, then `BASE_c_d1 …` for each,
/// then `c_EXTRA` for each. A computed name that INPUT (or an earlier computed column) already
/// has gets [`CLASH_SUFFIX`].
///
/// # Errors
/// An input column name that is empty (a computed name would be ambiguous).
pub fn output_names(input: &[String], run: &Computed<'_>) -> Result<Vec<String>> {
    if let Some(c) = run.columns.iter().find(|c| c.is_empty()) {
        bail!("the input column {c:?} has no name: name it in the header to run it");
    }
    let mut names: Vec<String> = input.to_vec();
    // A set of the names so far: a file of thousands of actuator columns is named in linear time.
    let mut taken: HashSet<String> = input.iter().cloned().collect();
    let mut push = |names: &mut Vec<String>, name: String| push_distinct(names, &mut taken, name);
    let outputs: Vec<String> = match run.columns {
        [_] => vec![run.base.to_string()],
        several => several
            .iter()
            .map(|c| format!("{}_{c}", run.base))
            .collect(),
    };
    for o in &outputs {
        push(&mut names, o.clone());
    }
    // The derivatives are named after the output as written (after any clash suffix).
    let written: Vec<String> = names.get(input.len()..).unwrap_or_default().to_vec();
    for o in &written {
        for k in 1..=run.derivatives {
            push(&mut names, format!("{o}_d{k}"));
        }
    }
    if let Some(extra) = run.extra {
        for c in run.columns {
            push(&mut names, format!("{c}_{extra}"));
        }
    }
    Ok(names)
}

/// Appends `name` to `names`, with [`CLASH_SUFFIX`] appended until `taken` (the names so far)
/// does not hold it, and records it in `taken`.
pub fn push_distinct(names: &mut Vec<String>, taken: &mut HashSet<String>, name: String) {
    let mut name = name;
    while taken.contains(&name) {
        name.push_str(CLASH_SUFFIX);
    }
    taken.insert(name.clone());
    names.push(name);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(
        input: &[&str],
        base: &str,
        columns: &[&str],
        n: usize,
        extra: Option<&str>,
    ) -> String {
        let input: Vec<String> = input.iter().map(|s| (*s).to_string()).collect();
        let run = Computed {
            base,
            columns,
            derivatives: n,
            extra,
        };
        output_names(&input, &run).map_or_else(|e| format!("error: {e}"), |v| v.join(","))
    }

    #[test]
    fn one_column_is_named_after_what_it_is() {
        assert_eq!(names(&["t", "x"], "y", &["x"], 0, None), "t,x,y");
        assert_eq!(
            names(&["t", "y_um"], "u_V", &["y_um"], 2, None),
            "t,y_um,u_V,u_V_d1,u_V_d2"
        );
        assert_eq!(
            names(&["y_um"], "u_V", &["y_um"], 0, Some("saturated")),
            "y_um,u_V,y_um_saturated"
        );
    }

    #[test]
    fn several_columns_get_their_column_in_the_name() {
        assert_eq!(
            names(&["a", "b", "record"], "y", &["a", "b"], 1, None),
            "a,b,record,y_a,y_b,y_a_d1,y_b_d1"
        );
    }

    #[test]
    fn a_name_the_input_has_gets_the_suffix() {
        assert_eq!(
            names(&["u_V", "y_um"], "u_V", &["y_um"], 1, None),
            "u_V,y_um,u_V_out,u_V_out_d1"
        );
        assert_eq!(
            names(&["y", "y_out", "x"], "y", &["x"], 0, None),
            "y,y_out,x,y_out_out"
        );
    }

    #[test]
    fn an_unnamed_input_column_is_refused() {
        assert!(names(&["", "x"], "y", &[""], 0, None).starts_with("error: "));
    }
}
