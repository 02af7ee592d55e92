//! The table rows of a record's samples ([`Rows`]), for error messages and plots over time.

/// The table rows of a record's samples, in sample order, held as runs of consecutive rows: a
/// record read in one piece is one run (16 bytes, where a row index per sample took 8 bytes a
/// sample). Build it by [`Rows::push`] or by collecting row indices.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Rows {
    /// (first row, index of its sample) of each run, in sample order; maximal runs, so equal
    /// sequences have equal runs.
    runs: Vec<(usize, usize)>,
    /// Number of samples.
    len: usize,
}

impl Rows {
    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no samples.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends the row of the next sample.
    pub fn push(&mut self, row: usize) {
        let extends = self
            .runs
            .last()
            .is_some_and(|&(first, at)| first.checked_add(self.len - at) == Some(row));
        if !extends {
            self.runs.push((row, self.len));
        }
        self.len += 1;
    }

    /// The rows as one range when they are one run of consecutive rows (`None` for no rows or
    /// several runs).
    #[must_use]
    pub fn as_run(&self) -> Option<std::ops::Range<usize>> {
        match self.runs[..] {
            [(first, _)] => Some(first..first + self.len),
            _ => None,
        }
    }

    /// The row of sample `i` (`None` past the end).
    #[must_use]
    pub fn get(&self, i: usize) -> Option<usize> {
        if i >= self.len {
            return None;
        }
        let k = self
            .runs
            .partition_point(|&(_, at)| at <= i)
            .checked_sub(1)?;
        self.runs.get(k).map(|&(first, at)| first + (i - at))
    }

    /// The rows of the samples, in order.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.runs
            .iter()
            .enumerate()
            .flat_map(move |(k, &(first, at))| {
                let end = self.runs.get(k + 1).map_or(self.len, |&(_, next)| next);
                first..first + (end - at)
            })
    }

    /// The rows of the samples `range` (clipped to the samples there are), run by run: a
    /// record cut into many segments costs a search per segment, not a walk from its start.
    #[must_use]
    pub fn slice(&self, range: std::ops::Range<usize>) -> Rows {
        let end = range.end.min(self.len);
        let mut out = Rows::default();
        let mut i = range.start;
        while i < end {
            let Some(k) = self.runs.partition_point(|&(_, at)| at <= i).checked_sub(1) else {
                break;
            };
            let Some(&(first, at)) = self.runs.get(k) else {
                break;
            };
            let run_end = self
                .runs
                .get(k + 1)
                .map_or(self.len, |&(_, next)| next)
                .min(end);
            // Runs of the source are maximal, so those of a slice are too.
            out.runs.push((first + (i - at), out.len));
            out.len += run_end - i;
            i = run_end;
        }
        out
    }
}

impl FromIterator<usize> for Rows {
    fn from_iter<I: IntoIterator<Item = usize>>(rows: I) -> Self {
        let mut out = Rows::default();
        for row in rows {
            out.push(row);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows held as runs give back every row pushed, by index, in order and in slices, and a
    /// record read in one piece is one run.
    /// Rows that are one run of consecutive rows give their range; others none.
    #[test]
    fn one_run_is_a_range() {
        let run: Rows = (4..9).collect();
        assert_eq!(run.as_run(), Some(4..9));
        let two: Rows = [4, 5, 7].into_iter().collect();
        assert_eq!(two.as_run(), None);
        assert_eq!(Rows::default().as_run(), None);
        assert_eq!(run.slice(1..3).as_run(), Some(5..7));
    }

    #[test]
    fn rows_are_kept_as_runs() {
        let pushed = [5, 6, 7, 2, 3, 9, 9, 10, 0];
        let rows: Rows = pushed.iter().copied().collect();
        assert_eq!(rows.len(), pushed.len());
        assert_eq!(rows.iter().collect::<Vec<_>>(), pushed);
        for (i, row) in pushed.iter().enumerate() {
            assert_eq!(rows.get(i), Some(*row), "sample {i}");
        }
        assert_eq!(rows.get(pushed.len()), None);
        assert_eq!(rows.runs.len(), 5);
        for (a, b) in [(0, 9), (1, 4), (2, 7), (4, 4), (8, 20)] {
            let want: Vec<usize> = pushed.iter().copied().skip(a).take(b.max(a) - a).collect();
            assert_eq!(
                rows.slice(a..b).iter().collect::<Vec<_>>(),
                want,
                "{a}..{b}"
            );
            assert_eq!(rows.slice(a..b), want.into_iter().collect::<Rows>());
        }
        let whole: Rows = (0..1_000_000).collect();
        assert_eq!((whole.runs.len(), whole.get(999_999)), (1, Some(999_999)));
        assert!(Rows::default().is_empty() && Rows::default().iter().next().is_none());
    }
}
