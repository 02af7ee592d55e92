//! `hyst run --model M` for a model with dynamics or a rate term: the records' time stamps give
//! each step, and the model runs with the one discretisation of `hyst_model::dynamics` for
//! each step's own length (`hyst_model::time`), under the model file's hold or `--hold`.
//!
//! - Direct: the command column in, the model output out (named after the model's output
//!   column).
//! - `--inverse`: Lemma 5.1's compensator, the desired output in, the command out (named after
//!   the model's input column). The desired output's derivatives come from the columns
//!   `<name>_d1 … <name>_dn` when the file has them all (n the plant order), else from a
//!   reference prefilter of order n and bandwidth `--prefilter-hz F`: the command then makes the
//!   plant track the prefiltered reference (written as the column `<name>_filtered`), not the
//!   raw one.
//!
//! OUTPUT holds every column of INPUT first, as `hyst run` does for a static model
//! ([`crate::naming`]).
//!
//! A record's nominal step and its gaps come from all its stamps, so INPUT is read twice (three
//! times when a record has a gap), streamed each time, in memory that does not grow with the
//! file: a first pass checks every cell the run reads and each record's time stamps
//! ([`Stamps`]), a pass over the records with gaps cuts them into parts ([`Parts`], each gap
//! said on stderr), the last runs the records and writes their rows.
//! A regular file is read again (as many bytes as the first pass read: rows appended meanwhile
//! are left out); anything else (a pipe) is copied into an unnamed temporary file in `TMPDIR`
//! during the first pass. Every error of the first pass comes before any row is run, and the
//! output is written atomically, so a failed run leaves none.

use std::cell::Cell;
use std::fs::File;
use std::io::{Read, Seek as _, SeekFrom, Write as _};
use std::path::Path;
use std::rc::Rc;

use anyhow::{anyhow, bail, Context, Result};
use hyst_io::number::sig;
use hyst_io::{CsvReader, CsvWriter};
use hyst_model::time::{time_column, Part, Parts, Stamps, TIME_COLUMNS};
use hyst_model::{
    Choice, Corner, Hold, ModelFile, Prefilter, SmoothModel, TimedCompensator, TimedRun,
};

use super::rows::Records;

/// What `hyst run` asks of a timed model (its arguments, as `crate::run` parsed them).
pub struct Options<'a> {
    /// `--inverse`.
    pub inverse: bool,
    /// `--column` (at most one is accepted).
    pub columns: &'a [String],
    /// `--time`.
    pub time: Option<&'a str>,
    /// `--record`.
    pub record: Option<&'a str>,
    /// `--no-record`.
    pub no_record: bool,
    /// `--prefilter-hz`.
    pub prefilter_hz: Option<f64>,
    /// `--hold`.
    pub hold: Option<Hold>,
    /// `--derivatives` (refused when non-zero).
    pub derivatives: u8,
    /// `--saturate` (refused).
    pub saturate: bool,
    /// INPUT.
    pub input: &'a Path,
    /// OUTPUT.
    pub output: &'a Path,
}

/// Runs a model with dynamics or a rate term (`model`, read from `path`) as `args` ask.
pub fn main(args: &Options<'_>, model: &ModelFile, path: &Path) -> Result<()> {
    let checked = check(args, model, path)?;
    let smooth = &checked;
    hyst_io::check_all_distinct(&[args.input, path], &[args.output])?;
    let mut input = Input::open(args.input, args.output)?;
    let (plan, mut records) = {
        let mut rows = input.first_pass()?;
        let plan = Plan::new(&rows, args, model, smooth, path)?;
        let records = plan.scan(&mut rows)?;
        (plan, records)
    };
    let fault = plan.first_fault(&mut records);
    for note in plan.cut_at_gaps(&input, &mut records, fault.as_ref().map(|f| f.0))? {
        eprintln!("{note}");
    }
    plan.check_bandwidth(args, &records, fault.as_ref().map(|f| f.0))?;
    // A refused time stamp stops the run before any row is written (to stdout, too): the
    // records before it are checked above, not run.
    if let Some((_, (line, message))) = &fault {
        // Time that goes back in a file of one record is most often the next record's start.
        let hint = if plan.record.is_none() && message.contains("goes back") {
            " (if the file holds several records, each with its own time, name the column that \
             tells them apart with --record COLUMN)"
        } else {
            ""
        };
        bail!(
            "{}:{line}: column {:?}: {message}{hint}",
            plan.source,
            plan.time_name
        );
    }
    // A record sampled far from the periods the model was fitted at (a time column in
    // milliseconds) runs without error, and wrong: said once, for the first.
    let off = records.iter().enumerate().find_map(|(k, r)| {
        r.parts
            .iter()
            .find_map(|p| model.provenance.period_note(p.nominal))
            .map(|note| (k, note))
    });
    if let Some((k, note)) = off {
        eprintln!("note: {}: record {}: {note}", plan.source, k + 1);
    }
    let mut rows = input.read_again()?;
    let mut out = CsvWriter::create(args.output, plan.output_names.clone())?;
    let mut cells = String::new();
    for record in &records {
        plan.run_record(smooth, args, record, &mut rows, &mut cells, &mut out)?;
    }
    if rows.next_cells()?.is_some() {
        bail!("{}: {CHANGED}", plan.source);
    }
    out.finish()?;
    Ok(())
}

/// What a second pass that does not find the rows of the first says.
const CHANGED: &str = "the file changed while it was read (its rows differ between the two \
                       passes a model with dynamics takes: the first finds each record's sample \
                       period); run it again on a file that is not being written";

/// INPUT, read twice.
struct Input<'a> {
    /// As given.
    path: &'a Path,
    /// Its name in messages.
    source: String,
    /// The open file.
    file: File,
    /// The copy of anything but a regular file (a pipe), written by the first pass.
    copy: Option<File>,
    /// The bytes the first pass read.
    read: Rc<Cell<u64>>,
    /// No progress display (OUTPUT is the terminal).
    quiet: bool,
}

impl<'a> Input<'a> {
    /// Opens INPUT (`output` decides whether progress is shown).
    fn open(path: &'a Path, output: &Path) -> Result<Self> {
        let (file, source) = hyst_io::open_file(path)?;
        Ok(Self {
            path,
            source,
            file,
            copy: None,
            read: Rc::default(),
            quiet: crate::progress::writes_to_terminal(output),
        })
    }

    /// The first pass: the rows as read, counted (and copied, for a pipe).
    fn first_pass(&mut self) -> Result<CsvReader<Box<dyn Read + '_>>> {
        if !self.file.metadata().is_ok_and(|m| m.is_file()) {
            let copy = tempfile::tempfile().map_err(|e| self.no_copy(&e))?;
            self.copy = Some(copy);
        }
        let counted = Counted {
            inner: &self.file,
            read: Rc::clone(&self.read),
            copy: self.copy.as_ref(),
            source: &self.source,
        };
        self.csv(Box::new(counted))
    }

    /// The bytes the first pass read, again (from the start of the file, or of the copy of a
    /// pipe): the second pass, and the search for an uneven step.
    fn read_again(&self) -> Result<CsvReader<Box<dyn Read + '_>>> {
        let mut file: &File = self.copy.as_ref().unwrap_or(&self.file);
        file.seek(SeekFrom::Start(0))
            .with_context(|| format!("{}: cannot read it again", self.source))?;
        self.csv(Box::new(file.take(self.read.get())))
    }

    /// A CSV reader of `bytes`, with the progress display of a long file.
    fn csv<'r>(&self, bytes: Box<dyn Read + 'r>) -> Result<CsvReader<Box<dyn Read + 'r>>> {
        let on_read = crate::progress::reading(self.path, crate::progress::LARGE_FILE, self.quiet);
        let counting: Box<dyn Read + 'r> = Box::new(hyst_io::CountingReader::new(bytes, on_read));
        Ok(CsvReader::new(counting, &self.source)?)
    }

    /// The error of a copy of a pipe that cannot be made.
    fn no_copy(&self, e: &std::io::Error) -> anyhow::Error {
        anyhow!(
            "{}: cannot copy it into a temporary file in {} (a model with dynamics reads its \
             input twice, and a pipe can be read once): {e} (set TMPDIR to a directory on a \
             disk with free space, or give a regular file)",
            self.source,
            std::env::temp_dir().display()
        )
    }
}

/// The first pass's reader: counts the bytes, and copies them (a pipe).
struct Counted<'a> {
    inner: &'a File,
    read: Rc<Cell<u64>>,
    copy: Option<&'a File>,
    source: &'a str,
}

impl Read for Counted<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let bytes = buf.get(..n).unwrap_or_default();
        if let Some(mut copy) = self.copy {
            copy.write_all(bytes).map_err(|e| {
                std::io::Error::new(
                    e.kind(),
                    format!(
                        "cannot copy {} into a temporary file in {} (set TMPDIR to a directory \
                         on a disk with free space): {e}",
                        self.source,
                        std::env::temp_dir().display()
                    ),
                )
            })?;
        }
        self.read.set(self.read.get() + n as u64);
        Ok(n)
    }
}

/// One record as the first pass found it.
struct Record {
    /// Its rows.
    rows: usize,
    /// Its time stamps, by line.
    stamps: Stamps<usize>,
    /// Its parts between gaps, once checked (one without a gap).
    parts: Vec<Part>,
    /// Whether it has a gap (its parts are found by one more pass).
    gaps: bool,
    /// Its median step (s), once checked.
    median: f64,
}

/// The columns of a timed run and what they are for.
struct Plan {
    /// INPUT's name in messages.
    source: String,
    /// The index of the column run.
    value: usize,
    /// The time column's name and index.
    time_name: String,
    time: usize,
    /// The desired output's derivative columns `<name>_d1 …`, when the file has them all.
    derivatives: Option<Vec<usize>>,
    /// The record column.
    record: Option<usize>,
    /// The plant order.
    order: usize,
    /// Whether the prefiltered reference is written (`<name>_filtered`).
    filtered: bool,
    /// INPUT's columns.
    width: usize,
    /// OUTPUT's columns.
    output_names: Vec<String>,
}

impl Plan {
    /// The columns of INPUT (`rows`, its header read) that the run takes.
    fn new<R: Read>(
        rows: &CsvReader<R>,
        args: &Options<'_>,
        model: &ModelFile,
        smooth: &SmoothModel,
        path: &Path,
    ) -> Result<Self> {
        let inverse = args.inverse;
        let name = args.columns.first().map_or_else(
            || {
                if inverse {
                    model.columns.output.clone()
                } else {
                    model.columns.input.clone()
                }
            },
            Clone::clone,
        );
        let value = rows.column(&name)?;
        let time_name = time_column(args.time, |n| rows.column_index(n).is_some())
            .map(str::to_string)
            .with_context(|| {
                format!(
                    "{}: the model {} has {}: it needs the records' time stamps, and the \
                         file has no column named {} (name it with --time COLUMN)",
                    rows.source(),
                    path.display(),
                    smooth.timed_parts(),
                    TIME_COLUMNS.join(", ")
                )
            })?;
        let time = rows.column(&time_name)?;
        let record = super::rows::record_column(rows, args.record, args.no_record, args.columns)?;
        let order = smooth.dynamics.map_or(0, |d| d.order());
        let derivatives: Option<Vec<usize>> = (1..=order)
            .map(|k| rows.column_index(&format!("{name}_d{k}")))
            .collect();
        if inverse && derivatives.is_none() && args.prefilter_hz.is_none() {
            bail!(
                "{}: the compensator of a plant of order {order} needs the desired output's \
                 first {order} time derivatives: give the columns {} or a reference prefilter \
                 (--prefilter-hz F, the bandwidth in Hz the command then tracks)",
                rows.source(),
                (1..=order)
                    .map(|k| format!("{name}_d{k}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let filtered = inverse && derivatives.is_none();
        let base = if inverse {
            &model.columns.input
        } else {
            &model.columns.output
        };
        let output_names = crate::naming::output_names(
            rows.names(),
            &crate::naming::Computed {
                base,
                columns: &[name.as_str()],
                derivatives: 0,
                extra: filtered.then_some("filtered"),
            },
        )?;
        Ok(Self {
            source: rows.source().to_string(),
            value,
            time_name,
            time,
            derivatives: if inverse { derivatives } else { None },
            record,
            order,
            filtered,
            width: rows.names().len(),
            output_names,
        })
    }

    /// The first pass: every cell the run reads, checked (a number where one is run), and each
    /// record's rows, first value and time stamps.
    fn scan<R: Read>(&self, rows: &mut CsvReader<R>) -> Result<Vec<Record>> {
        let mut records: Vec<Record> = Vec::new();
        let mut labels = Records::default();
        while let Some(line) = rows.next_cells()? {
            let x = rows.value(self.value, line)?;
            let t = rows.value(self.time, line)?;
            for &d in self.derivatives.iter().flatten() {
                rows.value(d, line)?;
            }
            let starts = match self.record {
                Some(r) => labels.starts(rows.cell_text(r, line)?),
                None => records.is_empty(),
            };
            let _ = x;
            if starts {
                records.push(Record {
                    rows: 0,
                    stamps: Stamps::default(),
                    parts: Vec::new(),
                    gaps: false,
                    median: f64::NAN,
                });
            }
            if let Some(record) = records.last_mut() {
                record.rows += 1;
                record.stamps.push(t, line);
            }
        }
        Ok(records)
    }

    /// Each record's nominal step and whether it has gaps, up to the first record whose stamps
    /// are refused: that record's index, the line and what is wrong.
    fn first_fault(&self, records: &mut [Record]) -> Option<(usize, (usize, String))> {
        for (k, record) in records.iter_mut().enumerate() {
            let check = match record.stamps.check() {
                Ok(c) => c,
                Err(fault) => return Some((k, fault)),
            };
            record.median = check.median;
            record.gaps = check.has_gaps();
            record.parts = vec![Part {
                start: 0,
                len: record.rows,
                nominal: check.mean,
            }];
        }
        None
    }

    /// Cuts the records with gaps (before the record `until`, the first refused) into parts,
    /// in one more pass over INPUT; returns what stderr says of each gap.
    fn cut_at_gaps(
        &self,
        input: &Input<'_>,
        records: &mut [Record],
        until: Option<usize>,
    ) -> Result<Vec<String>> {
        let end = until.unwrap_or(records.len());
        let Some(records) = records.get_mut(..end) else {
            return Ok(Vec::new());
        };
        if !records.iter().any(|r| r.gaps) {
            return Ok(Vec::new());
        }
        let mut notes = Vec::new();
        let mut rows = input.read_again()?;
        for record in records.iter_mut() {
            let check = record.stamps.check().ok().filter(|_| record.gaps);
            let mut parts = check.map(Parts::new);
            for _ in 0..record.rows {
                let line = rows
                    .next_cells()?
                    .with_context(|| format!("{}: {CHANGED}", self.source))?;
                if let Some(parts) = &mut parts {
                    parts.push(rows.value(self.time, line)?, line);
                }
            }
            if let Some(parts) = parts {
                let (parts, gaps) = parts.finish();
                for gap in gaps {
                    notes.push(format!(
                        "{}:{}: column {:?}: {}",
                        self.source,
                        gap.at,
                        self.time_name,
                        gap.describe()
                    ));
                }
                record.parts = parts;
            }
        }
        Ok(notes)
    }

    /// `--prefilter-hz F` against the sample period of every part of the records (before the
    /// record `until`, the first refused), before any row is run: whenever it is given, also
    /// when the derivative columns make it unused.
    fn check_bandwidth(
        &self,
        args: &Options<'_>,
        records: &[Record],
        until: Option<usize>,
    ) -> Result<()> {
        let Some(hz) = args.prefilter_hz else {
            return Ok(());
        };
        let parts = records
            .iter()
            .take(until.unwrap_or(records.len()))
            .flat_map(|r| &r.parts);
        for part in parts {
            Prefilter::check_bandwidth(hz, Some(part.nominal)).map_err(|e| {
                anyhow!(
                    "{}: --prefilter-hz {}: {e}",
                    self.source,
                    hyst_io::number::shortest(hz)
                )
            })?;
        }
        Ok(())
    }

    /// The next row of the last pass: its line, the value run and its time stamp; its cells
    /// (as read, for OUTPUT) into `cells`.
    fn next_row<R: Read>(
        &self,
        rows: &mut CsvReader<R>,
        cells: &mut String,
    ) -> Result<(usize, f64, f64)> {
        let line = rows
            .next_cells()?
            .with_context(|| format!("{}: {CHANGED}", self.source))?;
        cells.clear();
        rows.push_cells(line, cells)?;
        Ok((
            line,
            rows.value(self.value, line)?,
            rows.value(self.time, line)?,
        ))
    }

    /// Runs one record, part by part (each starting afresh), reading its rows from `rows`, and
    /// writes them.
    fn run_record<R: Read>(
        &self,
        smooth: &SmoothModel,
        args: &Options<'_>,
        record: &Record,
        rows: &mut CsvReader<R>,
        cells: &mut String,
        out: &mut CsvWriter,
    ) -> Result<()> {
        for part in &record.parts {
            if args.inverse {
                self.compensate_part(smooth, args, part, rows, cells, out)?;
            } else {
                self.run_part(smooth, part, rows, cells, out)?;
            }
        }
        Ok(())
    }

    /// The model over one part of a record.
    fn run_part<R: Read>(
        &self,
        smooth: &SmoothModel,
        part: &Part,
        rows: &mut CsvReader<R>,
        cells: &mut String,
        out: &mut CsvWriter,
    ) -> Result<()> {
        let source = &self.source;
        let mut run: Option<(TimedRun, f64)> = None;
        for _ in 0..part.len {
            let (line, x, t) = self.next_row(rows, cells)?;
            let at = || format!("{source}:{line}");
            let s = match &mut run {
                Some((r, before)) => {
                    let h = t - *before;
                    *before = t;
                    r.step_after(x, h)
                }
                None => {
                    let (r, _) = run.insert((
                        TimedRun::new(smooth, part.nominal, x)
                            .with_context(|| format!("{}: the model cannot start here", at()))?,
                        t,
                    ));
                    r.step(x)
                }
            }
            .with_context(|| format!("{}: input {x}", at()))?;
            out.write_row_after(cells, self.width, &[s.y])?;
        }
        Ok(())
    }

    /// The compensator over one part of a record.
    fn compensate_part<R: Read>(
        &self,
        smooth: &SmoothModel,
        args: &Options<'_>,
        part: &Part,
        rows: &mut CsvReader<R>,
        cells: &mut String,
        out: &mut CsvWriter,
    ) -> Result<()> {
        let source = &self.source;
        let order = self.order;
        let mut started: Option<(TimedCompensator, Option<Prefilter>, f64)> = None;
        let mut desired = Vec::with_capacity(order + 1);
        // The fastest corner of the loop the compensator met, and its line.
        let mut fastest: Option<(Corner, usize)> = None;
        for sample in 0..part.len {
            let (line, x, t) = self.next_row(rows, cells)?;
            let at = || format!("{source}:{line}");
            let (c, prefilter, h) = match &mut started {
                Some((c, p, before)) => {
                    let h = t - *before;
                    *before = t;
                    (c, p, h)
                }
                None => {
                    let c = TimedCompensator::new(smooth, x)
                        .with_context(|| format!("{}: the compensator cannot start here", at()))?;
                    let p = match (self.filtered, args.prefilter_hz) {
                        (true, Some(hz)) => Some(Prefilter::new(order, hz, part.nominal, x)?),
                        _ => None,
                    };
                    let (c, p, _) = started.insert((c, p, t));
                    (c, p, part.nominal)
                }
            };
            desired.clear();
            match (prefilter, &self.derivatives) {
                (Some(p), _) => desired.extend_from_slice(
                    &p.step_after(x, h)
                        .with_context(|| format!("{}: time step {h} s", at()))?[..=order],
                ),
                (None, Some(d)) => {
                    desired.push(x);
                    for &i in d {
                        desired.push(rows.value(i, line)?);
                    }
                }
                (None, None) => desired.push(x),
            }
            let (u, _) = c.step(&desired).with_context(|| {
                format!(
                    "{}: desired output {}",
                    at(),
                    hyst_io::number::sig(desired[0], 6)
                )
            })?;
            if let Some(corner) = c.fastest_corner().filter(|f| f.sample == sample) {
                fastest = Some((corner, line));
            }
            let computed = [u, desired[0]];
            let n = if self.filtered { 2 } else { 1 };
            out.write_row_after(cells, self.width, computed.get(..n).unwrap_or_default())?;
        }
        if let Some((corner, line)) = fastest.filter(|(c, _)| !c.resolved_by(part.nominal)) {
            let warning = corner.warning(part.nominal, "this record's period", |v| sig(v, 4));
            eprintln!("hyst run: warning: {source}:{line}: {warning}");
        }
        Ok(())
    }
}

/// Refuses, before the data is read, what a timed model cannot do as `args` ask; returns its
/// smooth model, under `--hold` when given.
fn check(args: &Options<'_>, model: &ModelFile, path: &Path) -> Result<SmoothModel> {
    let Some(smooth) = model.smooth.as_ref() else {
        bail!("{}: the model file holds no smooth model", path.display());
    };
    if args.derivatives > 0 || args.saturate || args.columns.len() > 1 {
        bail!(
            "{}: a model with dynamics or a rate term runs one column, without --derivatives or \
             --saturate (its compensator takes the desired output's derivatives from columns \
             <name>_d1 ... or from --prefilter-hz)",
            path.display()
        );
    }
    let inverse = args.inverse;
    if args.prefilter_hz.is_some() && !inverse {
        bail!("--prefilter-hz applies to --inverse (the compensator's reference)");
    }
    if inverse {
        TimedCompensator::check(smooth)
            .with_context(|| format!("{}: --inverse", path.display()))?;
    }
    let mut smooth = *smooth;
    if let Some(hold) = args.hold {
        let Some(d) = smooth.dynamics else {
            bail!(
                "--hold {}: {} has no dynamics (a rate term alone takes no hold)",
                hold.name(),
                path.display()
            );
        };
        if inverse {
            bail!(
                "--hold {}: the compensator of {} (--inverse) computes the command from the \
                 desired output's derivatives, whatever the hold: the hold changes how the plant \
                 follows the command, not the command (run the model without --inverse to see \
                 the plant's response under either hold)",
                hold.name(),
                path.display()
            );
        }
        smooth.dynamics = Some(d.with_hold(hold));
    }
    Ok(smooth)
}
