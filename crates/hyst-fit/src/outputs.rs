//! A model's output on the records of a dataset, given sample by sample ([`Outputs`]): what
//! the error statistics and the diagnosis read, without a vector of a long record's outputs
//! (8 bytes a sample, a third of the fit's memory at 10 M rows) held beside the data.

use hyst_model::SmoothModel;

use crate::data::Dataset;

/// The model's output on every sample of every record of a dataset, replayed as often as a
/// reader needs it.
pub trait Outputs {
    /// Calls `each(record, sample, output)` for every sample of every record of the dataset,
    /// in record order and sample order (`record` the index in
    /// [`Dataset::records`](crate::data::Dataset::records)). `false` when the model cannot run
    /// a record: `each` may then have seen part of the samples.
    fn replay(&self, each: &mut dyn FnMut(usize, usize, f64)) -> bool;
}

/// Outputs held: one vector per record, in record order.
impl Outputs for Vec<Vec<f64>> {
    fn replay(&self, each: &mut dyn FnMut(usize, usize, f64)) -> bool {
        for (i, y) in self.iter().enumerate() {
            for (j, v) in y.iter().enumerate() {
                each(i, j, *v);
            }
        }
        true
    }
}

/// The output of a smooth model on a dataset's records, run again for each replay: each
/// history ([`Dataset::histories`](crate::data::Dataset::histories): segments run on from one
/// another) from its estimated start (per history,
/// [`SmoothFit::starts`](crate::smooth::SmoothFit::starts)) or the start rule, a model with
/// dynamics or a rate term at each history's sample period.
pub struct ModelOutputs<'a> {
    /// The records.
    pub data: &'a Dataset,
    /// The model.
    pub model: &'a SmoothModel,
    /// The estimated start of each history (`None`: the start rule).
    pub starts: Option<&'a [f64]>,
}

impl Outputs for ModelOutputs<'_> {
    fn replay(&self, each: &mut dyn FnMut(usize, usize, f64)) -> bool {
        let timed = self.model.is_timed();
        for (index, h) in self.data.histories().into_iter().enumerate() {
            let band = self.starts.and_then(|s| s.get(index).copied());
            let period = if timed { h.period } else { None };
            // The record each sample of the history belongs to: its parts in order.
            let mut part = 0;
            let ran = self.model.run_timed(&h.input, period, band, |k, s| {
                while h.parts.get(part).is_some_and(|p| k >= p.1 + p.2) {
                    part += 1;
                }
                if let Some(&(record, start, _)) = h.parts.get(part) {
                    each(record, k - start, s.y);
                }
            });
            if ran.is_err() {
                return false;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::{ModelOutputs, Outputs};
    use crate::data::{DataOptions, Dataset};
    use crate::smooth::run_records;
    use hyst_core::{AnyK2Law, ScaledShaping};
    use hyst_io::Table;
    use hyst_model::{InitialState, SmoothModel};

    /// A replay gives each record the samples of its history's run that are its own, also for
    /// segments that run on from one another and from estimated starts; `run_records` holds
    /// the same.
    #[test]
    fn a_replay_gives_each_record_its_part_of_the_history() {
        let mut text = String::from("loop,u,y\n");
        for k in 0..500 {
            let u = (f64::from(k) * 0.05).sin() * (1.0 + f64::from(k) / 500.0);
            text.push_str(&format!("{},{u},{}\n", k / 250, 2.0 * u));
        }
        let table = Table::parse(text.as_bytes(), "d.csv").unwrap();
        let options = DataOptions {
            input: "u".into(),
            output: "y".into(),
            segment: Some(70),
            ..DataOptions::default()
        };
        let data = Dataset::from_table(&table, &options).unwrap();
        let model = SmoothModel {
            k1: 0.2,
            k2: AnyK2Law::Constant { value: 6.0 },
            input_shaping: ScaledShaping::identity(),
            output_shaping: ScaledShaping::identity(),
            initial_state: InitialState::Rising,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        };
        let histories = data.histories();
        assert_eq!((histories.len(), data.records.len()), (2, 8));
        let bands = [0.3, -0.2];
        for starts in [None, Some(&bands[..])] {
            // Each history run whole, then cut into its records.
            let mut expected = vec![Vec::new(); data.records.len()];
            for (index, h) in histories.iter().enumerate() {
                let band = starts.map(|s| s[index]);
                let mut y = Vec::new();
                model
                    .run_timed(&h.input, None, band, |_, s| y.push(s.y))
                    .unwrap();
                for &(i, start, len) in &h.parts {
                    expected[i] = y[start..start + len].to_vec();
                }
            }
            let mut replayed: Vec<Vec<f64>> = vec![Vec::new(); data.records.len()];
            let ran = ModelOutputs {
                data: &data,
                model: &model,
                starts,
            }
            .replay(&mut |i, j, y| {
                assert_eq!(replayed[i].len(), j);
                replayed[i].push(y);
            });
            assert!(ran);
            assert_eq!(replayed, expected);
            assert_eq!(run_records(&data, &model, starts).unwrap(), expected);
            let mut again = Vec::new();
            assert!(expected.replay(&mut |i, j, y| again.push((i, j, y))));
            assert_eq!(again.len(), 500);
        }
    }
}
