//! What each sample did to the estimator ([`Status`], [`Update`]) and how often ([`Counts`]).

/// What one sample did to the estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// The parameters were updated.
    Updated,
    /// The input has not travelled `rest` · k1 since the last update: nothing changed.
    Rest,
    /// The model has not met a reversal since it started (at its first sample, or after
    /// [`Adaptive::restart`](crate::adaptive::Adaptive::restart)): its state is still the start rule's guess, so nothing is learnt.
    Starting,
    /// The prediction error was within the dead zone: nothing changed.
    DeadZone,
    /// The command was not finite: the sample was skipped, the memory is unchanged.
    BadInput,
    /// The command was outside `input_range`: the model stepped, the parameters did not.
    OutOfRange,
    /// The measurement was not finite: the model stepped, the parameters did not.
    BadOutput,
    /// The model could not evaluate the sample or take the update (a float overflow, a
    /// product k1 k2 below the float resolution): the parameters did not change.
    Refused,
}

impl Status {
    /// Every status, in the order of their discriminants (the `HYST_ADAPT_*` codes of the C
    /// API).
    pub const ALL: [Status; 8] = [
        Status::Updated,
        Status::Rest,
        Status::Starting,
        Status::DeadZone,
        Status::BadInput,
        Status::OutOfRange,
        Status::BadOutput,
        Status::Refused,
    ];

    /// The name: `updated`, `rest`, `starting`, `dead_zone`, `bad_input`, `out_of_range`,
    /// `bad_output`, `refused` (Python's statuses, the keys of `hyst adapt`'s `counts`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Status::Updated => "updated",
            Status::Rest => "rest",
            Status::Starting => "starting",
            Status::DeadZone => "dead_zone",
            Status::BadInput => "bad_input",
            Status::OutOfRange => "out_of_range",
            Status::BadOutput => "bad_output",
            Status::Refused => "refused",
        }
    }
}

/// One sample's result: the one-step prediction (parameters before the update) and what
/// happened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Update<T> {
    /// ŷ, the prediction of the measured output (output units); NaN for [`Status::BadInput`].
    pub prediction: T,
    /// What the sample did.
    pub status: Status,
}

/// How many samples had each [`Status`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Counts {
    /// [`Status::Updated`].
    pub updated: u64,
    /// [`Status::Rest`].
    pub rest: u64,
    /// [`Status::Starting`].
    pub starting: u64,
    /// [`Status::DeadZone`].
    pub dead_zone: u64,
    /// [`Status::BadInput`].
    pub bad_input: u64,
    /// [`Status::OutOfRange`].
    pub out_of_range: u64,
    /// [`Status::BadOutput`].
    pub bad_output: u64,
    /// [`Status::Refused`].
    pub refused: u64,
}

/// The counts as the estimator keeps them: one counter per [`Status`], by discriminant (an
/// index, no branch per status on the hot path).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct Tally([u64; 8]);

impl Tally {
    pub(crate) fn add(&mut self, s: Status) {
        if let Some(c) = self.0.get_mut(s as usize) {
            *c = c.saturating_add(1);
        }
    }

    pub(crate) fn counts(&self) -> Counts {
        let [updated, rest, starting, dead_zone, bad_input, out_of_range, bad_output, refused] =
            self.0;
        Counts {
            updated,
            rest,
            starting,
            dead_zone,
            bad_input,
            out_of_range,
            bad_output,
            refused,
        }
    }
}

impl Counts {
    /// The count of status `s`.
    #[must_use]
    pub fn of(&self, s: Status) -> u64 {
        match s {
            Status::Updated => self.updated,
            Status::Rest => self.rest,
            Status::Starting => self.starting,
            Status::DeadZone => self.dead_zone,
            Status::BadInput => self.bad_input,
            Status::OutOfRange => self.out_of_range,
            Status::BadOutput => self.bad_output,
            Status::Refused => self.refused,
        }
    }

    /// The samples skipped for bad data: [`Status::BadInput`], [`Status::OutOfRange`],
    /// [`Status::BadOutput`].
    #[must_use]
    pub fn skipped(&self) -> u64 {
        self.bad_input
            .saturating_add(self.out_of_range)
            .saturating_add(self.bad_output)
    }
}
