//! First-order reversal curves exported without their point at saturation: every record rises
//! from its reversal point, so the data shows no loop, while the material has one. The default
//! fit starts each record as after a fall (`StartChoice::Auto`), finds the loop and is not
//! refused as "no hysteresis".

mod common;
use common::identify;
use hyst_core::{Hysteresis, Operator};
use hyst_fit::identify::Request;
use hyst_fit::{Dataset, FitError, Record};
use hyst_model::{InitialState, ShapingKind, Structure};

/// 20 curves of m = tanh(2 H(0.3, 6)[h]): each falls from saturation (h = 1.5) to its reversal
/// field (not recorded), then rises back (recorded, 60 points).
fn forc() -> Result<Dataset, FitError> {
    let mut op = Hysteresis::new(0.3, 6.0).map_err(|e| FitError::Invalid(e.to_string()))?;
    let mut records = Vec::new();
    for c in 0..20 {
        let reversal = 1.4 - 0.14 * f64::from(c + 1);
        for i in 0..=60 {
            op.step(1.5 - (1.5 - reversal) * f64::from(i) / 60.0);
        }
        let input: Vec<f64> = (1..=60)
            .map(|i| reversal + (1.5 - reversal) * f64::from(i) / 60.0)
            .collect();
        let output: Vec<f64> = input.iter().map(|&h| (2.0 * op.step(h)).tanh()).collect();
        let n = input.len();
        records.push(Record {
            id: i64::from(c),
            input: input.into(),
            output: output.into(),
            weight: hyst_fit::Weights::Unit(n),
            rows: (0..n).collect(),
            validation: false,
            continues: false,
            period: None,
        });
    }
    let template = Dataset::single(&[0.0], &[0.0]);
    Ok(Dataset::from_records("forc.csv", template.columns, records))
}

#[test]
fn curves_that_only_rise_start_as_after_a_fall_and_keep_their_loop() -> Result<(), FitError> {
    let data = forc()?;
    let request = Request {
        structure: Structure {
            output_shaping: ShapingKind::Tanh,
            ..Structure::default()
        },
        ..Request::default()
    };
    let done = identify(&data, &request)?;
    let fit = done
        .smooth
        .ok_or(FitError::Invalid("no smooth fit".into()))?;
    assert_eq!(fit.model.initial_state, InitialState::Falling);
    assert!(!done.report.findings.degenerate);
    assert!(
        done.report.findings.notes[0].starts_with("every record only rises"),
        "{:?}",
        done.report.findings.notes
    );
    let pct = 100.0 * fit.training.rms / done.report.output_span;
    assert!(pct < 0.5, "RMS {pct} % of span");
    Ok(())
}
