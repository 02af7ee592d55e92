//! On the host, with the platform's maths (as `hyst run`): every exported model reproduces
//! `hyst run --model` (and `--inverse --saturate`) bit for bit from the first sample, over the
//! signals of examples/firmware/export_signals.py in `$HYST_EXPORT_DIR`; the model with dynamics
//! (piezo_dyn) on its timed records, its compensator against `hyst run --model --inverse` with
//! the desired output's derivative columns.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hyst_core::Operator;
use hyst_export_check::*;

/// Column `name` of the CSV file `file` in the export folder.
fn column(file: &str, name: &str) -> Vec<f64> {
    let path = format!("{}/{file}", env!("HYST_EXPORT_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// Steps `op` over `input` (through `pre`) and checks every output's bits against `expected`.
fn check(what: &str, mut op: impl Operator<f64>, input: &[f64], expected: &[f64], pre: fn(f64) -> f64) {
    assert_eq!(input.len(), expected.len(), "{what}");
    for (i, (x, y)) in input.iter().zip(expected).enumerate() {
        let got = op.try_step(pre(*x)).unwrap_or_else(|e| panic!("{what} sample {i}: {e}"));
        assert_eq!(got.to_bits(), y.to_bits(), "{what} sample {i}: {got} against hyst run's {y}");
    }
    println!("{what}: {} samples bit-identical to hyst run", input.len());
}

#[test]
fn exported_models_equal_hyst_run() {
    let same = |x: f64| x;
    check("piezo", piezo::<f64>().unwrap(), &column("piezo.x.csv", "x"), &column("piezo.dir.csv", "y"), same);
    check("piezo inverse", piezo_inverse::<f64>().unwrap(), &column("piezo.y.csv", "y"), &column("piezo.inv.csv", "y"), same);
    check("steel", steel::<f64>().unwrap(), &column("steel.x.csv", "x"), &column("steel.dir.csv", "y"), same);
    check("steel inverse", steel_inverse::<f64>().unwrap(), &column("steel.y.csv", "y"), &column("steel.inv.csv", "y"), steel_clamp);
    check("friction", friction::<f64>().unwrap(), &column("friction.x.csv", "x"), &column("friction.dir.csv", "y"), same);
    check("piezo_pi", piezo_pi::<f64>().unwrap(), &column("piezo.x.csv", "x"), &column("piezo_pi.dir.csv", "y"), same);
    check("piezo_pi inverse", piezo_pi_inverse::<f64>().unwrap(), &column("piezo_pi.y.csv", "y"), &column("piezo_pi.inv.csv", "y"), same);
}

#[test]
fn exported_model_with_dynamics_equals_hyst_run() {
    // The model with its plant, over the commands of its timed record.
    let mut timed = piezo_dyn_timed::<f64>().unwrap();
    let x = column("piezo_dyn.x.csv", "x");
    let expected = column("piezo_dyn.dir.csv", "y");
    assert_eq!(x.len(), expected.len());
    for (i, (x, y)) in x.iter().zip(&expected).enumerate() {
        let got = timed.try_step(*x).unwrap_or_else(|e| panic!("piezo_dyn sample {i}: {e}"));
        assert_eq!(got.to_bits(), y.to_bits(), "piezo_dyn sample {i}: {got} against hyst run's {y}");
    }
    println!("piezo_dyn (with its plant): {} samples bit-identical to hyst run", x.len());
    // Its compensator, over the desired output and its derivatives.
    let desired: Vec<Vec<f64>> = (0..=PIEZO_DYN_ORDER)
        .map(|k| column("piezo_dyn.desired.csv", &if k == 0 { "y".to_string() } else { format!("y_d{k}") }))
        .collect();
    let expected = column("piezo_dyn.inv.csv", "y");
    let mut compensator = piezo_dyn_timed_compensator::<f64>(desired[0][0]).unwrap();
    for (i, u) in expected.iter().enumerate() {
        let row: [f64; PIEZO_DYN_ORDER + 1] = core::array::from_fn(|k| desired[k][i]);
        let got = compensator
            .track(piezo_dyn_reference(&row))
            .unwrap_or_else(|e| panic!("piezo_dyn compensator sample {i}: {e}"));
        assert_eq!(got.to_bits(), u.to_bits(), "piezo_dyn compensator sample {i}: {got} against hyst run's {u}");
    }
    println!("piezo_dyn compensator: {} samples bit-identical to hyst run", expected.len());
}
