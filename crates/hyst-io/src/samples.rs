//! Long columns of samples in bounded memory ([`Samples`], written by [`SamplesWriter`]): a
//! column longer than [`SPILL_AFTER`] values goes to an unnamed temporary file, mapped back
//! into memory as one slice. A thread drops the pages of every such mapping from the process's
//! resident memory every millisecond, so a fit of a long record holds what its passes are
//! reading, not the record: the operating system's page cache keeps the file while memory is
//! free and reads it back from disk when it is not.
//!
//! ```
//! # fn main() -> Result<(), hyst_io::IoError> {
//! use hyst_io::{Samples, SamplesWriter};
//!
//! let mut column = SamplesWriter::new(4); // to a file after 4 values
//! for i in 0..10 {
//!     column.push(f64::from(i))?;
//! }
//! let samples: Samples = column.finish()?;
//! assert!(samples.is_spilled());
//! assert_eq!(samples[7], 7.0);
//! assert_eq!(samples.slice(2..5), [2.0, 3.0, 4.0]);
//! # Ok(())
//! # }
//! ```
//!
//! The temporary file is in [`std::env::temp_dir`] (`TMPDIR`); on a RAM-backed file system
//! (tmpfs) it holds memory after all, so `TMPDIR` should name a directory on a disk.

use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::{Deref, Range};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use crate::error::IoError;

/// The number of values a [`SamplesWriter::default`] holds in memory (8 MB of `f64`) before it
/// moves its column to a temporary file, unless [`set_spill_after`] says otherwise.
pub const SPILL_AFTER: usize = 1 << 20;

/// The threshold of [`SamplesWriter::default`] ([`set_spill_after`]).
static SPILL_AFTER_NOW: AtomicUsize = AtomicUsize::new(SPILL_AFTER);

/// Sets the number of values a column read from then on holds in memory before it goes to a
/// temporary file (default [`SPILL_AFTER`]; `0`: every non-empty column; `usize::MAX`: none),
/// for the whole process. The values read are the same either way; `hyst` sets it from the
/// environment variable `HYST_SPILL_AFTER`.
pub fn set_spill_after(values: usize) {
    SPILL_AFTER_NOW.store(values, Ordering::Relaxed);
}

/// Bytes of the buffer in front of a spill file.
const SPILL_BUFFER: usize = 1 << 16;

/// A column of `f64` samples, as a slice (`Deref<Target = [f64]>`): held in memory, or in a
/// temporary file mapped into memory ([`SamplesWriter`] decides). Its parts
/// ([`Samples::slice`]), its clones and the join of neighbouring parts
/// ([`Samples::join`]) share the one column without a copy.
#[derive(Clone, Default)]
pub struct Samples {
    /// The whole column.
    store: Arc<Store>,
    /// The samples of it this one is.
    range: Range<usize>,
}

/// Where a column's samples are.
enum Store {
    /// In memory.
    Held(Vec<f64>),
    /// In a spill file (shared with the thread that trims its pages).
    Spilled(Arc<map::Spill>),
}

impl Default for Store {
    fn default() -> Self {
        Store::Held(Vec::new())
    }
}

impl Store {
    fn values(&self) -> &[f64] {
        match self {
            Store::Held(v) => v,
            Store::Spilled(spill) => spill.values(),
        }
    }
}

impl Samples {
    /// The samples of a whole store.
    fn whole(store: Store) -> Samples {
        let len = store.values().len();
        Samples {
            store: Arc::new(store),
            range: 0..len,
        }
    }

    /// Whether the samples are in a temporary file (not held in memory).
    #[must_use]
    pub fn is_spilled(&self) -> bool {
        matches!(*self.store, Store::Spilled(..))
    }

    /// Samples `range` (panics past the end, as slicing does), sharing the column.
    #[must_use]
    pub fn slice(&self, range: Range<usize>) -> Samples {
        let _ = &self[range.clone()]; // The bounds check of a slice.
        Samples {
            store: Arc::clone(&self.store),
            range: self.range.start + range.start..self.range.start + range.end,
        }
    }

    /// Whether `next` starts where `self` ends in the same column (neighbouring parts, such
    /// as segments cut from one record): [`Samples::join`] then makes no copy.
    #[must_use]
    pub fn adjoins(&self, next: &Samples) -> bool {
        Arc::ptr_eq(&self.store, &next.store) && self.range.end == next.range.start
    }

    /// `self` followed by `next`: the same column without a copy when `next` starts where
    /// `self` ends in it ([`Samples::adjoins`]), else a new column held in memory.
    #[must_use]
    pub fn join(&self, next: &Samples) -> Samples {
        if self.adjoins(next) {
            return Samples {
                store: Arc::clone(&self.store),
                range: self.range.start..next.range.end,
            };
        }
        self.iter().chain(next.iter()).copied().collect()
    }

    /// The samples as a vector (without a copy when they are a whole held column no other
    /// `Samples` shares).
    #[must_use]
    pub fn into_vec(self) -> Vec<f64> {
        let whole = self.range.start == 0 && self.range.end == self.store.values().len();
        match Arc::try_unwrap(self.store) {
            Ok(Store::Held(v)) if whole => v,
            Ok(store) => store.values()[self.range].to_vec(),
            Err(store) => store.values()[self.range].to_vec(),
        }
    }

    /// The samples of `values`, spilled past [`SPILL_AFTER`] as [`SamplesWriter::default`]
    /// spills.
    ///
    /// # Errors
    /// [`IoError::Spill`] if the temporary file cannot be written or mapped.
    pub fn collect_spilling(values: impl IntoIterator<Item = f64>) -> Result<Samples, IoError> {
        let mut writer = SamplesWriter::default();
        for v in values {
            writer.push(v)?;
        }
        writer.finish()
    }
}

impl Deref for Samples {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.store.values()[self.range.clone()]
    }
}

impl AsRef<[f64]> for Samples {
    fn as_ref(&self) -> &[f64] {
        self
    }
}

impl From<Vec<f64>> for Samples {
    fn from(values: Vec<f64>) -> Self {
        Samples::whole(Store::Held(values))
    }
}

impl From<&[f64]> for Samples {
    fn from(values: &[f64]) -> Self {
        Samples::whole(Store::Held(values.to_vec()))
    }
}

impl FromIterator<f64> for Samples {
    /// Held in memory (see [`Samples::collect_spilling`] for a long column).
    fn from_iter<I: IntoIterator<Item = f64>>(values: I) -> Self {
        Samples::whole(Store::Held(values.into_iter().collect()))
    }
}

impl<'a> IntoIterator for &'a Samples {
    type Item = &'a f64;
    type IntoIter = std::slice::Iter<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl fmt::Debug for Samples {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&**self, f)
    }
}

impl PartialEq for Samples {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl PartialEq<[f64]> for Samples {
    fn eq(&self, other: &[f64]) -> bool {
        **self == *other
    }
}

impl PartialEq<Vec<f64>> for Samples {
    fn eq(&self, other: &Vec<f64>) -> bool {
        **self == **other
    }
}

impl<const N: usize> PartialEq<[f64; N]> for Samples {
    fn eq(&self, other: &[f64; N]) -> bool {
        **self == other[..]
    }
}

/// Writes a column of samples value by value: held in memory up to its threshold, then
/// moved to an unnamed temporary file that [`SamplesWriter::finish`] maps back.
pub struct SamplesWriter {
    /// The values, while they are held.
    held: Vec<f64>,
    /// The spill file, once the column has gone past the threshold.
    file: Option<BufWriter<File>>,
    /// Values written.
    len: usize,
    /// Values held before the column goes to a file (`usize::MAX`: never).
    spill_after: usize,
}

impl Default for SamplesWriter {
    /// A writer that spills past [`SPILL_AFTER`] values ([`set_spill_after`]).
    fn default() -> Self {
        SamplesWriter::new(SPILL_AFTER_NOW.load(Ordering::Relaxed))
    }
}

impl SamplesWriter {
    /// A writer that holds up to `spill_after` values in memory and moves the column to a
    /// temporary file when it grows past them (`usize::MAX`: always held).
    #[must_use]
    pub fn new(spill_after: usize) -> Self {
        SamplesWriter {
            held: Vec::new(),
            file: None,
            len: 0,
            spill_after,
        }
    }

    /// The number of values written.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no value has been written.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends `value`.
    ///
    /// # Errors
    /// [`IoError::Spill`] if the temporary file cannot be created or written.
    pub fn push(&mut self, value: f64) -> Result<(), IoError> {
        // A full column spills before it takes the value: its vector never grows past the
        // threshold (nor doubles its capacity beyond it).
        if self.file.is_none() && self.held.len() >= self.spill_after {
            self.spill()?;
        }
        self.len += 1;
        match &mut self.file {
            Some(file) => file.write_all(&value.to_ne_bytes()).map_err(spill_error),
            None => {
                self.held.push(value);
                Ok(())
            }
        }
    }

    /// Moves the values held so far to a new temporary file.
    fn spill(&mut self) -> Result<(), IoError> {
        let file = tempfile::tempfile().map_err(spill_error)?;
        let mut file = BufWriter::with_capacity(SPILL_BUFFER, file);
        for v in &self.held {
            file.write_all(&v.to_ne_bytes()).map_err(spill_error)?;
        }
        self.held = Vec::new();
        self.file = Some(file);
        Ok(())
    }

    /// The values written, discarding any values held beyond them: a held column's slack
    /// goes back, a spilled one is mapped.
    ///
    /// # Errors
    /// [`IoError::Spill`] if the temporary file cannot be written or mapped.
    pub fn finish(mut self) -> Result<Samples, IoError> {
        match self.file.take() {
            None => {
                self.held.shrink_to_fit();
                Ok(Samples::whole(Store::Held(self.held)))
            }
            Some(file) => {
                let file = file.into_inner().map_err(|e| spill_error(e.into_error()))?;
                let spill = map::Spill::new(&file, self.len).map_err(spill_error)?;
                Ok(Samples::whole(Store::Spilled(spill)))
            }
        }
    }
}

/// The error of a spill file.
fn spill_error(source: std::io::Error) -> IoError {
    IoError::Spill {
        file: crate::error::MEMORY_SOURCE.to_string(),
        dir: std::env::temp_dir().display().to_string(),
        source,
    }
}

/// The mapping of a spill file, and the thread that keeps its pages out of resident memory.
/// The one module of this crate with `unsafe` code: mapping a file, and telling the kernel
/// that the mapping's pages are not needed.
#[allow(unsafe_code)]
mod map {
    use std::fs::File;
    use std::sync::{Arc, Condvar, Mutex, OnceLock, Weak};
    use std::time::Duration;

    use memmap2::Mmap;

    /// How often the mapped pages leave resident memory.
    const TRIM_PERIOD: Duration = Duration::from_millis(1);

    /// A spill file mapped into memory, read-only.
    pub(super) struct Spill {
        map: Mmap,
        len: usize,
    }

    impl Spill {
        /// Maps `len` values of `file`, and has its pages trimmed while it lives.
        pub(super) fn new(file: &File, len: usize) -> std::io::Result<Arc<Spill>> {
            // SAFETY: the file is an unnamed temporary file this process created and no longer
            // writes: nothing else can change it while it is mapped.
            let map = unsafe { Mmap::map(file)? };
            if map.len() != len * 8 || map.as_ptr().align_offset(align_of::<f64>()) != 0 {
                return Err(std::io::Error::other(format!(
                    "the temporary file holds {} bytes, not {} values",
                    map.len(),
                    len
                )));
            }
            let spill = Arc::new(Spill { map, len });
            trim(&spill);
            Ok(spill)
        }

        /// The values.
        pub(super) fn values(&self) -> &[f64] {
            let ptr = self.map.as_ptr().cast::<f64>();
            // SAFETY: the mapping is `len` × 8 bytes, aligned for f64 (both checked in `new`),
            // lives as long as `self`, and is never written; every bit pattern is an f64.
            unsafe { std::slice::from_raw_parts(ptr, self.len) }
        }

        /// Drops the mapping's pages from the process's resident memory (the next read maps
        /// them again from the page cache, or from disk).
        #[cfg(unix)]
        fn trim(&self) {
            // SAFETY: the mapping is read-only and shared, so its pages are the file's:
            // dropped, they read back the same values.
            let _ = unsafe {
                self.map
                    .unchecked_advise(memmap2::UncheckedAdvice::DontNeed)
            };
        }
    }

    /// The spills alive, and the signal that there are some.
    struct Live {
        spills: Mutex<Vec<Weak<Spill>>>,
        some: Condvar,
    }

    /// Keeps `spill`'s pages out of resident memory while it lives: every [`TRIM_PERIOD`], one
    /// thread (started with the first spill, waiting while there is none) drops the pages of
    /// every live spill. Where it cannot start, the pages stay until the kernel reclaims them.
    #[cfg(unix)]
    fn trim(spill: &Arc<Spill>) {
        static LIVE: OnceLock<Arc<Live>> = OnceLock::new();
        let live = LIVE.get_or_init(|| {
            let live = Arc::new(Live {
                spills: Mutex::new(Vec::new()),
                some: Condvar::new(),
            });
            let trimmer = Arc::clone(&live);
            // A thread that does not start leaves the pages to the kernel's reclaim.
            let _ = std::thread::Builder::new()
                .name("hyst-trim".into())
                .spawn(move || trim_forever(&trimmer));
            live
        });
        if let Ok(mut spills) = live.spills.lock() {
            spills.push(Arc::downgrade(spill));
            live.some.notify_one();
        }
    }

    #[cfg(not(unix))]
    fn trim(_: &Arc<Spill>) {}

    /// Asks the scheduler for short slices for the calling thread (Linux ≥ 6.12, `EEVDF`):
    /// a thread that wakes with a short slice has an early deadline and preempts a busy one at
    /// once, so the trimming keeps its period while the fit's threads fill every core. Where
    /// the kernel refuses, the thread keeps the default slice.
    #[cfg(target_os = "linux")]
    fn short_slices() {
        /// `struct sched_attr` of sched_setattr(2).
        #[repr(C)]
        struct SchedAttr {
            size: u32,
            policy: u32,
            flags: u64,
            nice: i32,
            priority: u32,
            runtime: u64,
            deadline: u64,
            period: u64,
        }
        let attr = SchedAttr {
            size: size_of::<SchedAttr>() as u32,
            policy: 0, // SCHED_OTHER
            flags: 0,
            nice: 0,
            priority: 0,
            runtime: 100_000, // ns: the shortest slice the kernel takes
            deadline: 0,
            period: 0,
        };
        // SAFETY: sched_setattr reads `size` bytes of a valid, initialised sched_attr for the
        // calling thread (pid 0); it changes nothing else.
        let _ = unsafe { libc::syscall(libc::SYS_sched_setattr, 0, &raw const attr, 0) };
    }

    #[cfg(not(target_os = "linux"))]
    fn short_slices() {}

    /// The trimming thread's loop.
    #[cfg(unix)]
    fn trim_forever(live: &Live) {
        short_slices();
        loop {
            let alive: Vec<Arc<Spill>> = {
                let Ok(mut spills) = live.spills.lock() else {
                    return;
                };
                spills.retain(|s| s.strong_count() > 0);
                while spills.is_empty() {
                    spills = match live.some.wait(spills) {
                        Ok(s) => s,
                        Err(_) => return,
                    };
                    spills.retain(|s| s.strong_count() > 0);
                }
                spills.iter().filter_map(Weak::upgrade).collect()
            };
            for spill in &alive {
                spill.trim();
            }
            drop(alive);
            std::thread::sleep(TRIM_PERIOD);
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn written(spill_after: usize, n: usize) -> Samples {
        let mut w = SamplesWriter::new(spill_after);
        for i in 0..n {
            w.push(i as f64 * 0.5).unwrap();
        }
        assert_eq!(w.len(), n);
        w.finish().unwrap()
    }

    #[test]
    fn a_column_past_its_threshold_is_spilled_and_reads_back_the_same() {
        for (spill_after, n, spilled) in
            [(4, 4, false), (4, 5, true), (0, 1, true), (8, 1000, true)]
        {
            let s = written(spill_after, n);
            assert_eq!(s.is_spilled(), spilled, "{spill_after} {n}");
            let expected: Vec<f64> = (0..n).map(|i| i as f64 * 0.5).collect();
            assert_eq!(s, expected);
        }
        assert!(written(usize::MAX, 100).iter().eq(&written(3, 100)[..]));
    }

    #[test]
    fn parts_of_a_spilled_column_share_it_and_match_a_held_one() {
        for spill_after in [usize::MAX, 2] {
            let s = written(spill_after, 10);
            assert_eq!(s.slice(3..6), [1.5, 2.0, 2.5]);
            assert_eq!(s.slice(7..10), [3.5, 4.0, 4.5]);
            assert!(s.slice(4..4).is_empty());
            let all = s.slice(0..7);
            assert_eq!(all.len(), 7);
            // A part of a part is the column's part.
            assert_eq!(all.slice(2..4), [1.0, 1.5]);
            let mut copy = all.clone().into_vec();
            copy[0] = 9.0;
            assert_eq!(all[0], 0.0);
            assert_eq!(copy[..2], [9.0, 0.5]);
            // Neighbouring parts join without a copy; others are copied.
            let (head, rest, whole) = (all.slice(0..3), all.slice(3..7), all.clone());
            let joined = head.join(&rest);
            assert_eq!(joined, whole);
            assert!(Arc::ptr_eq(&joined.store, &all.store));
            let swapped = rest.join(&head);
            assert_eq!(swapped, [1.5, 2.0, 2.5, 3.0, 0.0, 0.5, 1.0]);
            assert!(!Arc::ptr_eq(&swapped.store, &all.store));
            assert_eq!(all.slice(1..3).into_vec(), [0.5, 1.0]);
        }
    }

    #[test]
    fn pages_read_many_times_over_read_the_same() {
        // The trimming thread drops the pages between reads: each read maps them again.
        let s = written(16, 200_000);
        for _ in 0..3 {
            let sum: f64 = s.iter().sum();
            assert_eq!(sum, (0..200_000).map(|i| i as f64 * 0.5).sum::<f64>());
            std::thread::sleep(std::time::Duration::from_millis(12));
        }
    }

    #[test]
    fn collected_values_spill_as_the_default_writer_does() {
        let s = Samples::collect_spilling((0..SPILL_AFTER + 1).map(|i| i as f64)).unwrap();
        assert!(s.is_spilled());
        assert_eq!(s[SPILL_AFTER], SPILL_AFTER as f64);
        let s: Samples = (0..3).map(f64::from).collect();
        assert!(!s.is_spilled());
    }
}
