//! The pieces of a [`Dataset`](crate::data::Dataset): its records ([`Record`]), the
//! uninterrupted histories they form ([`History`]), and how a table is read into one
//! ([`DataOptions`]).

use std::borrow::Cow;

use hyst_io::Samples;
use hyst_model::TimeSteps;

use crate::rows::Rows;
use crate::weights::Weights;

/// One independent record (a loop, a reversal curve, an experiment): the model starts afresh
/// at its first sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// The record id (value of the record column, or the segment number).
    pub id: i64,
    /// Input samples (units of the input column); a long record's are in a temporary file
    /// ([`Samples`]).
    pub input: Samples,
    /// Output samples (units of the output column).
    pub output: Samples,
    /// Sample weights (≥ 0; [`Weights::Unit`] when no weight column is given).
    pub weight: Weights,
    /// Row index in the table of each sample (for error messages and plots over time).
    pub rows: Rows,
    /// Whether the record is held out for validation.
    pub validation: bool,
    /// Whether this record continues the history of the record before it: a segment cut by
    /// `--segment` from the same measurement. The model then runs on from the state the
    /// previous segment left (see [`Dataset::histories`](crate::data::Dataset::histories))
    /// instead of starting afresh.
    pub continues: bool,
    /// The time steps (s) from the time column, when the fit reads one
    /// ([`DataOptions::timed`]): the record's nominal step (its mean step) and each step that
    /// differs from it, as measured ([`hyst_model::time`]).
    pub period: Option<TimeSteps>,
}

/// Consecutive records that form one uninterrupted history (one measurement cut into
/// segments, or a single record): their samples in order, and where each record lies in them.
/// Its samples share the records' ([`Samples::join`]: segments cut from one record are one
/// part of its column again, without a copy).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct History<'a> {
    /// Input samples of all the records, in order.
    pub input: Samples,
    /// Output samples.
    pub output: Samples,
    /// Weights.
    pub weight: Cow<'a, Weights>,
    /// (index of the record in [`Dataset::records`](crate::data::Dataset::records), first
    /// sample in this history, length).
    pub parts: Vec<(usize, usize, usize)>,
    /// The time steps of its first record ([`Record::period`]), which its segments share.
    pub period: Option<&'a TimeSteps>,
}

impl Record {
    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        self.input.len()
    }
    /// Whether the record has no samples.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.input.is_empty()
    }
}

/// How to read a dataset from a table.
#[derive(Clone, Debug, Default)]
pub struct DataOptions {
    /// Input column.
    pub input: String,
    /// Output column.
    pub output: String,
    /// Record column; `None` looks for a column called `loop`, `curve_index`, `record` or
    /// `segment`.
    pub record: Option<String>,
    /// Use no record column even if one of the usual names exists.
    pub no_record: bool,
    /// Weight column.
    pub weight: Option<String>,
    /// Cut every record into consecutive segments of this many samples (each its own record).
    pub segment: Option<usize>,
    /// Record ids (after segmentation: segment numbers 0, 1, …) held out for validation.
    pub validate: Vec<i64>,
    /// Hold out every k-th record (the 2nd, …) for validation, if no explicit list is given.
    pub validate_every: Option<usize>,
    /// Time column (s); `None` looks for one of [`TIME_COLUMNS`](crate::data::TIME_COLUMNS).
    pub time: Option<String>,
    /// Read the time column and give every record its time steps (a model with dynamics or a
    /// rate term): the column must exist, and its stamps must increase; a gap splits a record
    /// ([`hyst_model::time`]).
    pub timed: bool,
}
