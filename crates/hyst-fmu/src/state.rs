//! FMU states (fmi2GetFMUstate …) and their serialised form (fmi2SerializeFMUstate …).
//!
//! A state is the whole instance state: the input x, the parameters k1, k2 (kind = "operator"),
//! the time of the last communication point and the committed history (the operator's memory,
//! or the model's first input and its evaluator's memory; none before the first fmi2DoStep).
//! The mode (initialisation, step mode, …) is not part of it: fmi2SetFMUstate keeps the mode.
//! The output y holds after fmi2DoStep is part of it in memory, not in the serialised form.
//! A model with dynamics or a rate term (`crate::timed`) also has the inputs x_d1 … x_dn, and
//! its history is a copy of its engine: such a state is never serialised (the FMU says
//! canSerializeFMUstate = false, and [`encode`] refuses it).
//!
//! # Serialised form, version 1 (all numbers little-endian)
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"hystFMUs"` |
//! | 8 | 4 | u32 version = 1 |
//! | 12 | 8 | u64 FNV-1a 64 of the FMU's GUID (a state of another FMU is refused) |
//! | 20 | 1 | kind: 0 operator, 1 model |
//! | 21 | 1 | inverse: 0 or 1 |
//! | 22 | 1 | history: 0 none, 1 operator memory, 2 smooth model memory, 3 Prandtl–Ishlinskii plays |
//! | 23 | 1 | 0 (reserved) |
//! | 24 | 8 | f64 x |
//! | 32 | 8 | f64 time |
//! | 40 | 16 | kind 0 only: f64 k1, f64 k2 |
//! | … | | history 1: a memory (below) |
//! | … | | history 2: f64 first, u8 0/1 (memory present), the memory if 1 |
//! | … | | history 3: f64 first, u32 n (= 128 plays), n × f64 play outputs, u8 0/1, f64 last output if 1 |
//! | end − 8 | 8 | u64 FNV-1a 64 of every byte before it |
//!
//! A memory (Definition 2.1) is f64 reversal input α0, f64 reversal output β0, f64 last input,
//! f64 last output, u8 direction (0 rising, 1 falling): 33 bytes.
//!
//! Reading checks everything before a state is accepted: the length (exact), magic, version,
//! checksum, GUID, kind and inverse, every flag and tag, every number finite; the memory is then
//! checked by the core through `Operator::set_memory` (see `Instance::engine_for`).

use hyst_core::{Direction, Memory, PlayMemory};
use hyst_model::file::fnv1a64;
use hyst_model::pi::MAX_PLAYS;
use hyst_model::{EvaluatorMemory, MAX_DYNAMICS};

use crate::timed::TimedEngine;

/// The first 8 bytes of a serialised state.
pub const MAGIC: [u8; 8] = *b"hystFMUs";
/// The version of the serialised form this FMU writes and reads.
pub const STATE_VERSION: u32 = 1;
/// Bytes before the body.
pub const HEADER_LEN: usize = 24;
/// Bytes of the trailing checksum.
pub const CHECKSUM_LEN: usize = 8;

/// The history-dependent part of a state.
#[derive(Clone, Debug)]
pub enum History {
    /// Nothing committed yet (before the first fmi2DoStep).
    Empty,
    /// The parametric operator's memory.
    Operator(Memory<f64>),
    /// The model: the input its evaluator started at, and the evaluator's memory.
    Model {
        /// `ModelFile::evaluator`'s `first`.
        first: f64,
        /// `Operator::memory` of the evaluator.
        memory: EvaluatorMemory,
    },
    /// A model with dynamics or a rate term: its engine, as it was (not serialisable).
    Timed(Box<TimedEngine>),
}

/// A saved instance state.
#[derive(Clone, Debug)]
pub struct FmuState {
    /// The input x (value reference 0).
    pub x: f64,
    /// The inputs x_d1 … x_d4 (the inverse of a model with dynamics; 0 for every other FMU,
    /// and not serialised).
    pub derivatives: [f64; MAX_DYNAMICS],
    /// (k1, k2) for kind = "operator"; `None` for a model.
    pub parameters: Option<(f64, f64)>,
    /// The end of the last communication step (fmi2GetRealStatus(fmi2LastSuccessfulTime)).
    pub time: f64,
    /// The output of the last committed sample that y holds until an input is set. Not
    /// serialised: a serialised state is of an FMU without dynamics or a rate term, whose
    /// output for x after the committed history is that same number (a repeated input moves
    /// nothing), so a state read back computes it again.
    pub held: Option<f64>,
    /// The committed history.
    pub history: History,
}

/// The FMU a serialised state belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Owner {
    /// FNV-1a 64 of the GUID.
    pub guid_hash: u64,
    /// kind = "model".
    pub model: bool,
    /// inverse = true.
    pub inverse: bool,
}

impl Owner {
    /// The owner of the FMU with this GUID, kind and direction.
    #[must_use]
    pub fn new(guid: &str, model: bool, inverse: bool) -> Self {
        Self {
            guid_hash: fnv1a64(guid.as_bytes()),
            model,
            inverse,
        }
    }
}

fn put_f64(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_memory(out: &mut Vec<u8>, m: &Memory<f64>) {
    for v in [
        m.reversal_input,
        m.reversal_output,
        m.last_input,
        m.last_output,
    ] {
        put_f64(out, v);
    }
    out.push(match m.direction {
        Direction::Rising => 0,
        Direction::Falling => 1,
    });
}

/// The serialised form of `state` (see the module docs). It is read back by [`decode`] only
/// when every number is finite.
///
/// # Errors
/// The state of a model with dynamics or a rate term (its history is an engine whose state
/// hyst-model does not expose), or with derivative inputs.
pub fn encode(state: &FmuState, owner: &Owner) -> Result<Vec<u8>, String> {
    if matches!(state.history, History::Timed(_)) || state.derivatives.iter().any(|d| *d != 0.0) {
        return Err(
            "the state of a model with dynamics or a rate term cannot be serialised \
                    (canSerializeFMUstate = false); fmi2GetFMUstate and fmi2SetFMUstate save \
                    and restore it in memory"
                .into(),
        );
    }
    let mut out = Vec::with_capacity(HEADER_LEN + 64 + CHECKSUM_LEN);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&STATE_VERSION.to_le_bytes());
    out.extend_from_slice(&owner.guid_hash.to_le_bytes());
    out.push(u8::from(owner.model));
    out.push(u8::from(owner.inverse));
    out.push(match &state.history {
        History::Empty => 0,
        History::Operator(_) => 1,
        History::Model {
            memory: EvaluatorMemory::Smooth(_),
            ..
        } => 2,
        History::Model {
            memory: EvaluatorMemory::Plays(_),
            ..
        } => 3,
        History::Timed(_) => 4, // refused above
    });
    out.push(0);
    put_f64(&mut out, state.x);
    put_f64(&mut out, state.time);
    if let Some((k1, k2)) = state.parameters {
        put_f64(&mut out, k1);
        put_f64(&mut out, k2);
    }
    match &state.history {
        History::Empty | History::Timed(_) => {}
        History::Operator(m) => put_memory(&mut out, m),
        History::Model { first, memory } => {
            put_f64(&mut out, *first);
            match memory {
                EvaluatorMemory::Smooth(m) => match m {
                    None => out.push(0),
                    Some(m) => {
                        out.push(1);
                        put_memory(&mut out, m);
                    }
                },
                EvaluatorMemory::Plays(p) => {
                    let n = u32::try_from(p.plays.len()).unwrap_or(u32::MAX);
                    out.extend_from_slice(&n.to_le_bytes());
                    for v in &p.plays {
                        put_f64(&mut out, *v);
                    }
                    match p.last_output {
                        None => out.push(0),
                        Some(y) => {
                            out.push(1);
                            put_f64(&mut out, y);
                        }
                    }
                }
            }
        }
    }
    let sum = fnv1a64(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    Ok(out)
}

/// Reads the body of a serialised state, every read checked.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let end = self.at.saturating_add(N);
        let slice = self.bytes.get(self.at..end).ok_or_else(|| {
            format!(
                "the state ends at byte {} inside {what} (its length is wrong)",
                self.bytes.len()
            )
        })?;
        let mut out = [0; N];
        out.copy_from_slice(slice);
        self.at = end;
        Ok(out)
    }

    fn u8(&mut self, what: &str) -> Result<u8, String> {
        let [b] = self.take::<1>(what)?;
        Ok(b)
    }

    fn flag(&mut self, what: &str) -> Result<bool, String> {
        match self.u8(what)? {
            0 => Ok(false),
            1 => Ok(true),
            v => Err(format!("{what} = {v}: must be 0 or 1")),
        }
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(what)?))
    }

    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(what)?))
    }

    /// A finite f64.
    fn f64(&mut self, what: &str) -> Result<f64, String> {
        let v = f64::from_le_bytes(self.take(what)?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("{what} = {v}: must be finite"))
        }
    }

    fn memory(&mut self) -> Result<Memory<f64>, String> {
        let reversal_input = self.f64("the reversal input")?;
        let reversal_output = self.f64("the reversal output")?;
        let last_input = self.f64("the last input")?;
        let last_output = self.f64("the last output")?;
        let direction = match self.u8("the direction")? {
            0 => Direction::Rising,
            1 => Direction::Falling,
            v => return Err(format!("the direction = {v}: must be 0 or 1")),
        };
        Ok(Memory {
            reversal_input,
            reversal_output,
            direction,
            last_input,
            last_output,
        })
    }
}

/// Reads a serialised state of the FMU `owner`, checking everything the bytes alone can show
/// (the memory itself is then checked by the core when it is restored into an operator).
///
/// # Errors
/// A message naming what is wrong: length, magic, version, checksum, GUID, kind, a flag, a
/// non-finite number.
pub fn decode(bytes: &[u8], owner: &Owner) -> Result<FmuState, String> {
    let len = bytes.len();
    if len < HEADER_LEN + 16 + CHECKSUM_LEN {
        return Err(format!(
            "{len} bytes: too short for a hyst FMU state (at least {})",
            HEADER_LEN + 16 + CHECKSUM_LEN
        ));
    }
    let (content, sum) = bytes.split_at(len - CHECKSUM_LEN);
    let mut r = Reader {
        bytes: content,
        at: 0,
    };
    let tag = r.header(sum, owner)?;
    let x = r.f64("x")?;
    let time = r.f64("time")?;
    let parameters = if owner.model {
        None
    } else {
        Some((r.f64("k1")?, r.f64("k2")?))
    };
    let history = r.history(tag, owner.model)?;
    if r.at != content.len() {
        return Err(format!(
            "{} bytes after the state's end (its length is wrong)",
            content.len() - r.at
        ));
    }
    Ok(FmuState {
        x,
        derivatives: [0.0; MAX_DYNAMICS],
        parameters,
        time,
        held: None,
        history,
    })
}

impl Reader<'_> {
    /// The header, checked in the order of its bytes (magic, version), then the checksum `sum`
    /// of all the content, then the owner (GUID, kind, inverse); returns the history tag.
    fn header(&mut self, sum: &[u8], owner: &Owner) -> Result<u8, String> {
        if self.take::<8>("the magic")? != MAGIC {
            return Err("not a hyst FMU state (wrong magic bytes)".into());
        }
        let version = self.u32("the version")?;
        if version != STATE_VERSION {
            return Err(format!(
                "state format version {version}; this FMU reads version {STATE_VERSION}"
            ));
        }
        let mut stored = [0; CHECKSUM_LEN];
        stored.copy_from_slice(sum);
        if u64::from_le_bytes(stored) != fnv1a64(self.bytes) {
            return Err("the checksum does not match: the bytes are corrupted or truncated".into());
        }
        if self.u64("the GUID hash")? != owner.guid_hash {
            return Err("the state belongs to another FMU (its GUID differs)".into());
        }
        let model = self.flag("the kind")?;
        if model != owner.model {
            return Err(format!(
                "the state is of kind \"{}\", this FMU is of kind \"{}\"",
                kind_name(model),
                kind_name(owner.model)
            ));
        }
        let inverse = self.flag("the inverse flag")?;
        if inverse != owner.inverse {
            return Err(format!(
                "the state has inverse = {inverse}, this FMU inverse = {}",
                owner.inverse
            ));
        }
        let tag = self.u8("the history tag")?;
        let reserved = self.u8("the reserved byte")?;
        if reserved != 0 {
            return Err(format!("the reserved byte = {reserved}: must be 0"));
        }
        Ok(tag)
    }

    /// The history of tag `tag` for an FMU of kind "model" (`model`) or "operator".
    fn history(&mut self, tag: u8, model: bool) -> Result<History, String> {
        Ok(match (tag, model) {
            (0, _) => History::Empty,
            (1, false) => History::Operator(self.memory()?),
            (2, true) => {
                let first = self.f64("the model's first input")?;
                let memory = if self.flag("the memory flag")? {
                    Some(self.memory()?)
                } else {
                    None
                };
                History::Model {
                    first,
                    memory: EvaluatorMemory::Smooth(memory),
                }
            }
            (3, true) => {
                let first = self.f64("the model's first input")?;
                History::Model {
                    first,
                    memory: EvaluatorMemory::Plays(self.plays()?),
                }
            }
            (t, _) => {
                return Err(format!(
                    "history tag {t}: not a history of kind \"{}\"",
                    kind_name(model)
                ))
            }
        })
    }

    /// A Prandtl–Ishlinskii model's memory: the play outputs and the last output.
    fn plays(&mut self) -> Result<Box<PlayMemory<f64, MAX_PLAYS>>, String> {
        let n = self.u32("the number of plays")?;
        if usize::try_from(n).ok() != Some(MAX_PLAYS) {
            return Err(format!("{n} plays: must be {MAX_PLAYS}"));
        }
        let mut plays = [0.0; MAX_PLAYS];
        for p in &mut plays {
            *p = self.f64("a play output")?;
        }
        let last_output = if self.flag("the last output flag")? {
            Some(self.f64("the last output")?)
        } else {
            None
        };
        Ok(Box::new(PlayMemory { plays, last_output }))
    }
}

fn kind_name(model: bool) -> &'static str {
    if model {
        "model"
    } else {
        "operator"
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn memory(direction: Direction) -> Memory<f64> {
        Memory {
            reversal_input: 0.25,
            reversal_output: 0.125,
            direction,
            last_input: -0.5,
            last_output: -0.375,
        }
    }

    #[test]
    fn every_history_round_trips_and_only_for_its_owner() {
        let mut plays = [0.0; MAX_PLAYS];
        plays[0] = 0.5;
        plays[1] = -1.5;
        let cases = [
            (false, Some((0.2, 8.0)), History::Empty),
            (
                false,
                Some((0.2, 8.0)),
                History::Operator(memory(Direction::Falling)),
            ),
            (true, None, History::Empty),
            (
                true,
                None,
                History::Model {
                    first: 1.0,
                    memory: EvaluatorMemory::Smooth(None),
                },
            ),
            (
                true,
                None,
                History::Model {
                    first: 1.0,
                    memory: EvaluatorMemory::Smooth(Some(memory(Direction::Rising))),
                },
            ),
            (
                true,
                None,
                History::Model {
                    first: -2.0,
                    memory: EvaluatorMemory::Plays(Box::new(PlayMemory {
                        plays,
                        last_output: Some(3.0),
                    })),
                },
            ),
        ];
        for (model, parameters, history) in cases {
            let state = FmuState {
                x: 0.75,
                derivatives: [0.0; MAX_DYNAMICS],
                parameters,
                time: 12.5,
                held: None,
                history,
            };
            for inverse in [false, true] {
                let owner = Owner::new("{g}", model, inverse);
                let bytes = encode(&state, &owner).unwrap();
                let back = decode(&bytes, &owner).unwrap();
                assert_eq!(format!("{back:?}"), format!("{state:?}"));
                for other in [
                    Owner::new("{h}", model, inverse),
                    Owner::new("{g}", !model, inverse),
                    Owner::new("{g}", model, !inverse),
                ] {
                    assert!(decode(&bytes, &other).is_err());
                }
            }
        }
    }
}
