//! Rate terms: the measured friction damper, a viscous force on an operator, and the model kinds
//! that take no dynamics.

use super::*;
use crate::truths::*;

/// The measured friction damper (data/friction-damper): fitted on the 0.25 Hz and 1 Hz
/// records, it predicts the 0.5 Hz and 2 Hz ones; `--rate-term viscous` finds no support for a
/// viscous term there (the damper's force barely follows velocity) and leaves it out. Beside it,
/// a Coulomb + viscous fit F = F_c sign(v) + c v + F_0 by least squares.
#[test]
fn friction_damper_predicts_other_frequencies_without_an_invented_rate_term() {
    let dir = tempfile::tempdir().unwrap();
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/friction-damper/friction_damper_sines.csv");
    let text = std::fs::read_to_string(source).unwrap();
    // Text labels to record numbers 0..9, in file order.
    let mut labels: Vec<String> = Vec::new();
    let mut rows: Vec<[f64; 4]> = Vec::new();
    let mut csv = String::from("record,t_s,x_mm,v_mm_s,force_kN\n");
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if labels.last().map(String::as_str) != Some(f[0]) {
            labels.push(f[0].to_string());
        }
        let id = labels.len() - 1;
        csv.push_str(&format!("{id},{},{},{},{}\n", f[2], f[3], f[4], f[5]));
        let v = |i: usize| f[i].parse::<f64>().unwrap();
        rows.push([id as f64, v(3), v(4), v(5)]);
    }
    let data = dir.path().join("damper.csv");
    std::fs::write(&data, csv).unwrap();
    let held_out = [3.0, 4.0, 5.0, 9.0]; // 0.5 Hz and 2 Hz
    let model = dir.path().join("m.toml");
    let fit = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "fit",
            data.to_str().unwrap(),
            "--input",
            "x_mm",
            "--output",
            "force_kN",
            "--validate",
            "3,4,5,9",
            "--json",
            "-o",
            model.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        serde_json::from_str(&HYST.stdout(&args)).unwrap()
    };
    let plain = fit(&[]);
    let rated = fit(&["--rate-term", "viscous"]);
    let pct = |j: &serde_json::Value, set: &str| {
        j["model"]["metrics"][set]["rms_pct_span"].as_f64().unwrap()
    };
    // Coulomb + viscous by least squares on the training records.
    let (lo, hi) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r[3]), b.max(r[3]))
        });
    let features = |r: &[f64; 4]| [r[2].signum(), r[2], 1.0];
    let (mut ata, mut atb) = ([[0.0; 3]; 3], [0.0; 3]);
    for r in rows.iter().filter(|r| !held_out.contains(&r[0])) {
        let x = features(r);
        for i in 0..3 {
            atb[i] += x[i] * r[3];
            for j in 0..3 {
                ata[i][j] += x[i] * x[j];
            }
        }
    }
    let coef = solve3(ata, atb);
    let rms = |validation: bool| {
        let e: Vec<f64> = rows
            .iter()
            .filter(|r| held_out.contains(&r[0]) == validation)
            .map(|r| {
                let x = features(r);
                x[0] * coef[0] + x[1] * coef[1] + x[2] * coef[2] - r[3]
            })
            .collect();
        100.0 * (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt() / (hi - lo)
    };
    println!(
        "friction damper (train 0.25 + 1 Hz, validate 0.5 + 2 Hz), RMS % of span: stop form \
         {:.2} / {:.2}; with --rate-term viscous {:.2} / {:.2} (rate term: {}); Coulomb + \
         viscous (F_c = {:.3} kN, c = {:.2e} kN s/mm) {:.2} / {:.2}",
        pct(&plain, "training"),
        pct(&plain, "validation"),
        pct(&rated, "training"),
        pct(&rated, "validation"),
        rated["notes"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|n| n.as_str())
            .find(|n| n.contains("rate term"))
            .unwrap_or("none"),
        coef[0],
        coef[1],
        rms(false),
        rms(true)
    );
    assert!(rated["model"]["rate"].is_null(), "a rate term was invented");
    assert!(pct(&plain, "validation") < 1.2 * pct(&plain, "training"));
    assert!(pct(&plain, "validation") < rms(true));
}

/// The solution of a 3 × 3 system by Cramer's rule.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let mut x = [0.0; 3];
    for (k, slot) in x.iter_mut().enumerate() {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = b[i];
        }
        *slot = det(m) / d;
    }
    x
}

/// Dynamics belong to the smooth model: a Prandtl–Ishlinskii fit with them is refused.
#[test]
fn dynamics_with_a_prandtl_ishlinskii_model_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.csv");
    let rows: Vec<Vec<f64>> = (0..200)
        .map(|k| {
            let t = f64::from(k) * 0.01;
            vec![t, t.sin(), t.sin() + 0.1 * t.cos()]
        })
        .collect();
    write_csv(&data, "t,u,y", &rows);
    let model = dir.path().join("m.toml");
    let out = HYST
        .command()
        .args([
            "fit",
            data.to_str().unwrap(),
            "--input",
            "u",
            "--output",
            "y",
        ])
        .args(["--model-kind", "pi", "--dynamics", "1", "-o"])
        .arg(&model)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("smooth model"),
        "{err}"
    );
    assert!(!model.exists());
}

/// A viscous force on a counterclockwise hysteresis, y = 3 H(0.2, 5)[v] + 1 + 0.05 v̇: the
/// force turns the loops clockwise, yet with `--rate-term viscous` the fit finds the operator
/// form and c (the form the loops suggest is overruled, with a note).
#[test]
fn a_viscous_force_on_an_operator_is_found_whatever_the_loops_look_like() {
    let dir = tempfile::tempdir().unwrap();
    let h = 1e-3;
    let v: Vec<f64> = (0..5000)
        .map(|k| {
            let t = k as f64 * h;
            (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (t / 0.3).min(1.0)
                + 0.4 * (2.0 * std::f64::consts::PI * 4.1 * t + 1.0).sin()
        })
        .collect();
    let mut op = InitialState::Rising
        .start(Hysteresis::new(0.2, 5.0).unwrap(), v[0])
        .unwrap();
    let z = hysteresis(&mut op, &v);
    let rows: Vec<Vec<f64>> = (0..v.len())
        .map(|k| {
            let rate = if k == 0 { 0.0 } else { (v[k] - v[k - 1]) / h };
            vec![k as f64 * h, v[k], 3.0 * z[k] + 1.0 + 0.05 * rate]
        })
        .collect();
    let data = dir.path().join("visc.csv");
    write_csv(&data, "t,v,y", &rows);
    let model = dir.path().join("m.toml");
    let json: serde_json::Value = serde_json::from_str(&HYST.stdout(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "v",
        "--output",
        "y",
        "--rate-term",
        "viscous",
        "--json",
        "-o",
        model.to_str().unwrap(),
    ]))
    .unwrap();
    let c = json["model"]["rate"]["c"].as_f64().unwrap();
    println!("viscous force on an operator: c = {c:.5} (0.05)");
    assert!((c / 0.05 - 1.0).abs() < 0.02, "{c}");
    assert!(
        json["model"]["smooth"]["form"].is_null(),
        "the operator form"
    );
}
