//! The weights of a record's samples ([`Weights`]): unit weights, the usual case, hold no
//! vector.

use std::ops::Range;

use hyst_io::{IoError, Samples};

/// The weights of a record's samples (each ≥ 0): all 1 without a weight column, held as a
/// count (a 10 M-sample record's vector of ones took 80 MB), else one per sample (a part of
/// the weight column, in a temporary file when it is long: [`Samples`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Weights {
    /// This many samples, each of weight 1.
    Unit(usize),
    /// One weight per sample.
    Each(Samples),
}

impl Default for Weights {
    fn default() -> Self {
        Weights::Unit(0)
    }
}

impl From<Vec<f64>> for Weights {
    fn from(weights: Vec<f64>) -> Self {
        Weights::Each(weights.into())
    }
}

impl Weights {
    /// The weights `values`: a count when every one is 1.
    #[must_use]
    pub fn from_values(values: Vec<f64>) -> Weights {
        if values.iter().all(|&w| w == 1.0) {
            Weights::Unit(values.len())
        } else {
            values.into()
        }
    }

    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            Weights::Unit(n) => *n,
            Weights::Each(w) => w.len(),
        }
    }

    /// Whether there are no samples.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The weight of sample `i` (`None` past the end).
    #[must_use]
    pub fn get(&self, i: usize) -> Option<f64> {
        match self {
            Weights::Unit(n) => (i < *n).then_some(1.0),
            Weights::Each(w) => w.get(i).copied(),
        }
    }

    /// The weights in sample order.
    pub fn iter(&self) -> Iter<'_> {
        match self {
            Weights::Unit(n) => Iter::Unit(std::iter::repeat_n(1.0, *n)),
            Weights::Each(w) => Iter::Each(w.iter()),
        }
    }

    /// One weight per sample, as a slice; `None` for unit weights.
    #[must_use]
    pub fn as_slice(&self) -> Option<&[f64]> {
        match self {
            Weights::Unit(_) => None,
            Weights::Each(w) => Some(w),
        }
    }

    /// The weights of samples `range` (clipped to the samples there are), sharing the column.
    #[must_use]
    pub fn slice(&self, range: Range<usize>) -> Weights {
        let end = range.end.min(self.len());
        let start = range.start.min(end);
        match self {
            Weights::Unit(_) => Weights::Unit(end - start),
            Weights::Each(w) => Weights::Each(w.slice(start..end)),
        }
    }

    /// Whether `next` continues these weights without a copy when appended ([`Weights::extend`]):
    /// both unit, or neighbouring parts of one column ([`Samples::adjoins`]).
    #[must_use]
    pub fn adjoins(&self, next: &Weights) -> bool {
        match (self, next) {
            (Weights::Unit(_), Weights::Unit(_)) => true,
            (Weights::Each(a), Weights::Each(b)) => a.adjoins(b),
            _ => false,
        }
    }

    /// Appends the weights of `other` (the next part of the same column without a copy:
    /// [`Samples::join`]).
    pub fn extend(&mut self, other: &Weights) {
        *self = match (&*self, other) {
            (Weights::Unit(n), Weights::Unit(m)) => Weights::Unit(n + m),
            (Weights::Each(a), Weights::Each(b)) => Weights::Each(a.join(b)),
            _ => self.iter().chain(other.iter()).collect::<Vec<f64>>().into(),
        };
    }

    /// The weights as a vector, one per sample.
    #[must_use]
    pub fn to_vec(&self) -> Vec<f64> {
        self.iter().collect()
    }

    /// Every weight mapped by `f` (unit weights stay a count where `f(1) == 1`; a long column
    /// goes to a temporary file).
    ///
    /// # Errors
    /// [`IoError::Spill`] if that file cannot be written.
    pub fn map(&mut self, f: impl Fn(f64) -> f64) -> Result<(), IoError> {
        match self {
            Weights::Unit(n) => {
                let one = f(1.0);
                if one != 1.0 {
                    *self = Samples::collect_spilling(std::iter::repeat_n(one, *n))
                        .map(Weights::Each)?;
                }
            }
            Weights::Each(w) => *w = Samples::collect_spilling(w.iter().map(|&v| f(v)))?,
        }
        Ok(())
    }

    /// Sets the weights of samples `range` (clipped) to `value` (the weights are copied into
    /// memory).
    pub fn fill(&mut self, range: Range<usize>, value: f64) {
        let end = range.end.min(self.len());
        let start = range.start.min(end);
        if start == end || matches!(self, Weights::Unit(_)) && value == 1.0 {
            return;
        }
        let mut each = self.to_vec();
        each[start..end].fill(value);
        *self = each.into();
    }
}

/// The weight of a sample of [`Weights::Unit`], for [`Weights`]' indexing.
static ONE: f64 = 1.0;

impl std::ops::Index<usize> for Weights {
    type Output = f64;

    /// The weight of sample `i`.
    ///
    /// # Panics
    /// If `i` is not below [`Weights::len`], as a slice's indexing.
    fn index(&self, i: usize) -> &f64 {
        match self {
            Weights::Unit(n) => {
                assert!(i < *n, "sample {i} of {n} weights");
                &ONE
            }
            Weights::Each(w) => &w[i],
        }
    }
}

/// The iterator of [`Weights::iter`]: the weights by value, in sample order.
#[derive(Clone, Debug)]
pub enum Iter<'a> {
    /// Unit weights.
    Unit(std::iter::RepeatN<f64>),
    /// One weight per sample.
    Each(std::slice::Iter<'a, f64>),
}

impl Iterator for Iter<'_> {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        match self {
            Iter::Unit(it) => it.next(),
            Iter::Each(it) => it.next().copied(),
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        match self {
            Iter::Unit(it) => it.size_hint(),
            Iter::Each(it) => it.size_hint(),
        }
    }
}

impl ExactSizeIterator for Iter<'_> {}

impl<'a> IntoIterator for &'a Weights {
    type Item = f64;
    type IntoIter = Iter<'a>;

    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::Weights;

    /// Unit weights behave as a vector of ones, and become one when a weight is not 1.
    #[test]
    fn unit_weights_are_ones() {
        let mut w = Weights::Unit(3);
        assert_eq!(w.to_vec(), [1.0; 3]);
        assert_eq!((w.get(2), w.get(3), w.as_slice()), (Some(1.0), None, None));
        w.extend(&Weights::from_values(vec![1.0]));
        assert_eq!(w, Weights::Unit(4));
        assert_eq!(w.slice(1..9), Weights::Unit(3));
        w.map(|v| v / 1.0).unwrap();
        assert_eq!(w, Weights::Unit(4));
        w.extend(&Weights::from_values(vec![0.5]));
        assert_eq!(w, Weights::from(vec![1.0, 1.0, 1.0, 1.0, 0.5]));
        let mut u = Weights::Unit(2);
        u.extend(&Weights::Unit(1));
        assert_eq!(u, Weights::Unit(3));
        u.extend(&w.slice(3..5));
        assert_eq!(u.to_vec(), [1.0, 1.0, 1.0, 1.0, 0.5]);
        u.fill(0..2, 0.0);
        assert_eq!(u.to_vec(), [0.0, 0.0, 1.0, 1.0, 0.5]);
        let mut v = Weights::Unit(2);
        v.map(|x| 2.0 * x).unwrap();
        assert_eq!(v, Weights::from(vec![2.0, 2.0]));
        // Neighbouring parts of one column join back into it.
        let column = Weights::from(vec![0.5, 2.0, 3.0, 4.0]);
        let mut head = column.slice(0..1);
        head.extend(&column.slice(1..4));
        assert_eq!(head, column);
        let mut z = Weights::Unit(3);
        z.fill(1..2, 0.0);
        assert_eq!(z.to_vec(), [1.0, 0.0, 1.0]);
        assert_eq!(z.iter().len(), 3);
    }
}
