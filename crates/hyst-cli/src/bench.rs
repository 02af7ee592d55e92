//! `hyst bench`: ns per sample of the operators and of the yardsticks, measured in one process
//! (rounds of ~10 ms batches, interleaved, the fastest batch of each kept), with the speed goals
//! as ratios (timings on shared machines are noisy; ratios measured in one
//! run are what to compare). The workloads and the measuring are hyst-bench's
//! (`crate::workloads`); the plain-C peer of the inverse is timed by `hyst-bench`, not here.

use std::time::Duration;

use anyhow::{bail, Result};
use hyst_io::number::shortest;
use serde_json::json;

use crate::bench_fit::{self, FitFigures, FIT_OVER_RUN_GOAL};
use crate::workloads::{calibrate, measure, Inputs, Suite as _, NAMES};
use hyst_bank::{force_isa, isa, Isa};

/// Arguments of `hyst bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print JSON (keys direct_ns, inverse_ns, inverse_d2_ns, model_ns, exp_ns, lambert_w0_ns,
    /// bank_inverse_ns, bank_direct_ns, bank_inverse_f32_ns (banks of 1,024 channels in blocks of
    /// 64 ticks, ns per channel-sample), fitted_static_ns, fitted_dynamics_ns, adaptive_ns, the
    /// goal ratios and goals_met, the banks' ratios to the scalar operators and to each other,
    /// bank_inverse_f32_channel_samples_per_s, bank_goals_met, dynamics_over_static,
    /// dynamics_goal_met, adaptive_over_direct and adaptive_goal_met, kernel, the bank's
    /// instruction set; the same banks tick by tick (one `step` per tick of the 64, ns per
    /// channel-sample): bank_tick_inverse_ns, bank_tick_direct_ns, bank_tick_inverse_f32_ns, next
    /// to 1,024 scalar operators stepped once a tick each, scalar_tick_inverse_ns and
    /// scalar_tick_direct_ns, with bank_tick_inverse_over_scalar, bank_tick_direct_over_scalar,
    /// bank_tick_inverse_f32_over_bank_tick_inverse and bank_tick_goals_met (inverse <= 0.25,
    /// direct <= 0.33, f32 / f64 <= 0.5), and with the AVX2 kernel forced in the same run (a
    /// processor without AVX-512; null where there is no AVX2 + FMA): bank_avx2_tick_inverse_ns,
    /// bank_avx2_tick_direct_ns, bank_avx2_tick_inverse_f32_ns, bank_avx2_tick_inverse_over_scalar,
    /// bank_avx2_tick_direct_over_scalar, bank_avx2_tick_inverse_f32_over_bank_avx2_tick_inverse
    /// and bank_avx2_tick_goals_met (inverse <= 0.30, direct <= 0.40); and the long-record fit's
    /// fit_rows, fit_seconds, run_seconds, fit_over_run, fit_goal_met, fit_peak_bytes,
    /// fit_peak_bytes_per_row, fit_memory_goal_met and run_peak_bytes, null without --fit-rows)
    /// instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Run the banks on this kernel instead of the best this processor has (to see how a
    /// processor without AVX-512 fares): avx512, avx2 (with FMA), sse2 or portable.
    #[arg(long, value_name = "ISA", value_parser = ["avx512", "avx2", "sse2", "portable"])]
    pub kernel: Option<String>,
    /// Total measuring time of the whole run, in seconds, in (0, 60] (wall clock; the run
    /// takes this plus about 0.2 s of calibration). The time is shared by the 20 workloads,
    /// measured in interleaved rounds of batches of about 5 ms each (at least 5 rounds).
    #[arg(long, default_value_t = 1.0)]
    pub seconds: f64,
    /// Also fit a random walk of this many rows (a reversal every three samples or so) with
    /// `hyst fit` and run the fitted model on it with `hyst run`, this executable as child
    /// processes: the fit's time over the run's (goal ≤ 6) and its peak memory (goal ≤ 256 MB
    /// at 10,000,000 rows). 0 (the default) leaves it out; it takes a few seconds a million
    /// rows, besides --seconds.
    #[arg(long, value_name = "ROWS", default_value_t = 0)]
    pub fit_rows: usize,
}

/// The prefix of the JSON keys of the banks tick by tick with the AVX2 kernel forced, and the
/// key of their goals' verdict.
const AVX2_TICK: &str = "bank_avx2_tick";
const AVX2_TICK_MET: &str = "bank_avx2_tick_goals_met";

/// Runs `hyst bench`.
pub fn main(args: Args) -> Result<()> {
    if !(args.seconds.is_finite() && args.seconds > 0.0 && args.seconds <= 60.0) {
        bail!("--seconds {}: must be in (0, 60]", shortest(args.seconds));
    }
    if let Some(name) = &args.kernel {
        let isa = Isa::ALL.into_iter().find(|i| i.name() == name);
        if let Some(Err(isa)) = isa.map(|i| force_isa(Some(i))) {
            bail!(
                "--kernel {}: this processor cannot run it (it runs {})",
                isa.name(),
                Isa::ALL
                    .into_iter()
                    .filter(|i| i.available())
                    .map(Isa::name)
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    let inputs = Inputs::new();
    for (index, (name, _)) in NAMES.iter().enumerate() {
        if inputs.available(index) && !inputs.run(index).is_finite() {
            bail!("benchmark workload {name:?} gave a non-finite checksum");
        }
    }
    let calls = calibrate(&inputs);
    let best = measure(&inputs, &calls, Duration::from_secs_f64(args.seconds));
    let ratios = Ratios::of(&best);
    let fit = if args.fit_rows > 0 {
        Some(bench_fit::measure(args.fit_rows)?)
    } else {
        None
    };
    if args.json {
        print_json(&best, &ratios, fit.as_ref())
    } else {
        print_table(&best, &ratios);
        if let Some(fit) = &fit {
            print_fit(fit);
        }
        Ok(())
    }
}

/// The goals as ratios measured in one run, from the fastest batch of each workload.
struct Ratios {
    /// Scalar H⁻¹ over exp.
    inverse: f64,
    /// Scalar H over Lambert W0 + exp.
    direct: f64,
    /// The banks against the scalar operators (per channel-sample over per sample), and the
    /// f32 bank against the f64 one: (JSON key, name, ratio).
    bank: [(&'static str, &'static str, f64); 4],
    /// The f32 inverse bank's channel-samples per second.
    f32_rate: f64,
    /// The goals of the bank, each a ratio measured in this run (the last is a rate).
    bank_goals: [(&'static str, bool); 4],
    /// A fitted model with dynamics of order 2 over the same model without (goal: at
    /// most 2).
    dynamics: f64,
    /// The adaptive estimator (k1, k2, gain, offset) over the direct operator, per sample
    /// (goal: at most 10).
    adaptive: f64,
    /// The banks tick by tick on the kernel of the run (the bank's goals).
    tick: TickRatios,
    /// The banks tick by tick with the AVX2 kernel forced (their own goals; `None` where the
    /// processor has no AVX2 + FMA).
    avx2_tick: Option<TickRatios>,
}

/// The banks stepped tick by tick against 1,024 scalar operators stepped the same way, and the
/// f32 bank against the f64 one, with their goals.
struct TickRatios {
    /// (JSON key, name, ratio): inverse, direct, f32 / f64.
    ratios: [(String, String, f64); 3],
    /// (goal, met), each a ratio of this run.
    goals: Vec<(String, bool)>,
    /// The JSON key of the verdict over `goals`.
    met_key: &'static str,
}

impl TickRatios {
    /// The ratios of the ns per channel-sample `inverse`, `direct`, `inverse32` (banks) and
    /// `scalar_inverse`, `scalar_direct`; `prefix` "bank_tick" or "bank_avx2_tick", `what` the
    /// way they ran (in the goals' names), and the goals' bounds on the three ratios (none
    /// where `None`).
    fn of(
        prefix: &str,
        what: &str,
        [inverse, direct, inverse32]: [f64; 3],
        [scalar_inverse, scalar_direct]: [f64; 2],
        bounds: [Option<f64>; 3],
        met_key: &'static str,
    ) -> Self {
        let ratios = [
            inverse / scalar_inverse,
            direct / scalar_direct,
            inverse32 / inverse,
        ];
        let names = [
            ("bank H^-1 f64", "scalar H^-1"),
            ("bank H f64", "scalar H"),
            ("bank H^-1 f32", "bank H^-1 f64"),
        ];
        let goals = names
            .iter()
            .zip(bounds)
            .zip(ratios)
            .filter_map(|((&(bank, under), bound), ratio)| {
                let bound = bound?;
                Some((
                    format!("{bank} {what} <= {bound} x {under}"),
                    ratio <= bound,
                ))
            })
            .collect();
        let [i, d, f] = ratios;
        let [ki, kd, kf] = Self::keys(prefix);
        Self {
            ratios: [
                (ki, format!("bank H^-1 f64 / scalar H^-1, {what}"), i),
                (kd, format!("bank H f64 / scalar H, {what}"), d),
                (kf, format!("bank H^-1 f32 / f64, {what}"), f),
            ],
            goals,
            met_key,
        }
    }

    /// The JSON keys of the three ratios for `prefix`.
    fn keys(prefix: &str) -> [String; 3] {
        [
            format!("{prefix}_inverse_over_scalar"),
            format!("{prefix}_direct_over_scalar"),
            format!("{prefix}_inverse_f32_over_{prefix}_inverse"),
        ]
    }

    /// Whether every goal is met.
    fn met(&self) -> bool {
        self.goals.iter().all(|(_, met)| *met)
    }
}

impl Ratios {
    /// The ratios of the ns per sample `best` (in the order of [`NAMES`]).
    fn of(best: &[f64]) -> Self {
        let at = |i: usize| best.get(i).copied().unwrap_or(f64::NAN);
        let (direct, inverse, exp, w0) = (at(0), at(1), at(4), at(5));
        let inverse_ratio = inverse / exp;
        let direct_ratio = direct / (w0 + exp);
        // The banks against the scalar operators (per channel-sample over per sample), and the
        // f32 bank against the f64 one.
        let (bank_inverse, bank_direct) = (at(6) / inverse, at(7) / direct);
        let f32_over_f64 = at(8) / at(6);
        let bank = [
            (
                "bank_inverse_over_inverse",
                "bank H^-1 f64 / scalar H^-1",
                bank_inverse,
            ),
            (
                "bank_direct_over_direct",
                "bank H f64 / scalar H",
                bank_direct,
            ),
            (
                "bank_inverse_f32_over_inverse",
                "bank H^-1 f32 / scalar H^-1 f64",
                at(8) / inverse,
            ),
            (
                "bank_inverse_f32_over_bank_inverse",
                "bank H^-1 f32 / bank H^-1 f64",
                f32_over_f64,
            ),
        ];
        let f32_rate = 1e9 / at(8);
        let bank_goals = [
            ("bank H^-1 f64 <= 0.25 x scalar H^-1", bank_inverse <= 0.25),
            ("bank H f64 <= 0.33 x scalar H", bank_direct <= 0.33),
            ("bank H^-1 f32 <= 0.5 x bank H^-1 f64", f32_over_f64 <= 0.5),
            ("bank H^-1 f32 >= 500 M channel-samples/s", f32_rate >= 5e8),
        ];
        let scalar_ticks = [at(15), at(16)];
        let tick = TickRatios::of(
            "bank_tick",
            "tick",
            [at(12), at(13), at(14)],
            scalar_ticks,
            [Some(0.25), Some(0.33), Some(0.5)],
            "bank_tick_goals_met",
        );
        let avx2 = [at(17), at(18), at(19)];
        let avx2_tick = avx2.iter().all(|ns| ns.is_finite()).then(|| {
            TickRatios::of(
                AVX2_TICK,
                "tick (AVX2)",
                avx2,
                scalar_ticks,
                [Some(0.30), Some(0.40), None],
                AVX2_TICK_MET,
            )
        });
        Self {
            inverse: inverse_ratio,
            direct: direct_ratio,
            bank,
            f32_rate,
            bank_goals,
            dynamics: at(10) / at(9),
            adaptive: at(11) / direct,
            tick,
            avx2_tick,
        }
    }

    /// Whether every goal of the bank is met.
    fn bank_goals_met(&self) -> bool {
        self.bank_goals.iter().all(|&(_, met)| met)
    }
}

/// Prints the ns per sample `best` and the `ratios` as JSON.
fn print_json(best: &[f64], ratios: &Ratios, fit: Option<&FitFigures>) -> Result<()> {
    let mut map = serde_json::Map::new();
    for ((_, key), ns) in NAMES.iter().zip(best) {
        // Null for a workload this processor does not run.
        map.insert((*key).to_string(), json!(ns.is_finite().then_some(*ns)));
    }
    map.insert("inverse_over_exp".into(), json!(ratios.inverse));
    map.insert("direct_over_w0_plus_exp".into(), json!(ratios.direct));
    map.insert(
        "goals_met".into(),
        json!(ratios.inverse <= 1.5 && ratios.direct <= 1.5),
    );
    for (key, _, ratio) in ratios.bank {
        map.insert(key.into(), json!(ratio));
    }
    map.insert(
        "bank_inverse_f32_channel_samples_per_s".into(),
        json!(ratios.f32_rate),
    );
    map.insert("bank_goals_met".into(), json!(ratios.bank_goals_met()));
    map.insert("dynamics_over_static".into(), json!(ratios.dynamics));
    map.insert("dynamics_goal_met".into(), json!(ratios.dynamics <= 2.0));
    map.insert("adaptive_over_direct".into(), json!(ratios.adaptive));
    map.insert("adaptive_goal_met".into(), json!(ratios.adaptive <= 10.0));
    map.insert("kernel".into(), json!(isa().name()));
    map.insert(ratios.tick.met_key.into(), json!(ratios.tick.met()));
    for (key, _, ratio) in &ratios.tick.ratios {
        map.insert(key.clone(), json!(ratio));
    }
    // The AVX2 keys are there without AVX2 too, null.
    let avx2 = ratios.avx2_tick.as_ref();
    for (i, key) in TickRatios::keys(AVX2_TICK).into_iter().enumerate() {
        let ratio = avx2.and_then(|t| t.ratios.get(i)).map(|r| r.2);
        map.insert(key, json!(ratio));
    }
    map.insert(AVX2_TICK_MET.into(), json!(avx2.map(TickRatios::met)));
    let peak = fit.and_then(|f| f.peak_bytes);
    for (key, value) in [
        ("fit_rows", json!(fit.map_or(0, |f| f.rows))),
        ("fit_seconds", json!(fit.map(|f| f.fit_s))),
        ("run_seconds", json!(fit.map(|f| f.run_s))),
        ("fit_over_run", json!(fit.map(FitFigures::ratio))),
        (
            "fit_goal_met",
            json!(fit.map(|f| f.ratio() <= FIT_OVER_RUN_GOAL)),
        ),
        ("fit_peak_bytes", json!(peak)),
        (
            "fit_peak_bytes_per_row",
            json!(fit.and_then(|f| Some(f.peak_bytes? / f.rows as f64))),
        ),
        (
            "fit_memory_goal_met",
            json!(fit.and_then(FitFigures::memory_goal_met)),
        ),
        ("run_peak_bytes", json!(fit.and_then(|f| f.run_peak_bytes))),
    ] {
        map.insert(key.into(), value);
    }
    outln!("{}", serde_json::to_string_pretty(&map)?);
    Ok(())
}

/// Prints the ns per sample `best` and the `ratios` as a table, with the goals met or not.
fn print_table(best: &[f64], ratios: &Ratios) {
    let (inverse_ratio, direct_ratio) = (ratios.inverse, ratios.direct);
    outln!("{:<40} {:>10}", "workload", "ns/sample");
    for ((name, _), ns) in NAMES.iter().zip(best) {
        if ns.is_finite() {
            outln!("{name:<40} {ns:>10.2}");
        } else {
            outln!("{name:<40} {:>10}", "no AVX2");
        }
    }
    outln!();
    outln!(
        "goal inverse <= 1.5 x exp:            {inverse_ratio:.2} ({})",
        verdict(inverse_ratio <= 1.5)
    );
    outln!(
        "goal direct <= 1.5 x (lambert_w0+exp): {direct_ratio:.2} ({})",
        verdict(direct_ratio <= 1.5)
    );
    outln!();
    outln!("{:<37} {}", "bank kernel:", isa().name());
    for (_, name, ratio) in ratios.bank {
        outln!("{:<37} {ratio:.2}", format!("{name}:"));
    }
    outln!(
        "{:<37} {:.0} M",
        "bank H^-1 f32 channel-samples/s:",
        ratios.f32_rate / 1e6
    );
    outln!();
    for (goal, met) in ratios.bank_goals {
        outln!("goal {goal:<42} {}", verdict(met));
    }
    outln!();
    for tick in std::iter::once(&ratios.tick).chain(&ratios.avx2_tick) {
        for (_, name, ratio) in &tick.ratios {
            outln!("{:<45} {ratio:.2}", format!("{name}:"));
        }
        for (goal, met) in &tick.goals {
            outln!("goal {goal:<50} {}", verdict(*met));
        }
        outln!();
    }
    outln!(
        "goal fitted model with dynamics <= 2 x static: {:.2} ({})",
        ratios.dynamics,
        verdict(ratios.dynamics <= 2.0)
    );
    outln!(
        "goal adaptive estimator <= 10 x direct H:      {:.2} ({})",
        ratios.adaptive,
        verdict(ratios.adaptive <= 10.0)
    );
}

/// How a goal's line ends: "met" or "NOT met".
fn verdict(met: bool) -> &'static str {
    if met {
        "met"
    } else {
        "NOT met"
    }
}

/// Prints the long-record fit's figures under the table, with its goals met or not.
fn print_fit(fit: &FitFigures) {
    outln!();
    outln!(
        "random walk of {} rows: hyst fit {:.2} s, hyst run {:.2} s",
        fit.rows,
        fit.fit_s,
        fit.run_s
    );
    outln!(
        "goal fit <= {FIT_OVER_RUN_GOAL} x run:                    {:.2} ({})",
        fit.ratio(),
        verdict(fit.ratio() <= FIT_OVER_RUN_GOAL)
    );
    match fit.peak_bytes {
        Some(peak) => outln!(
            "fit peak memory: {:.0} MB, {:.0} bytes a row{}",
            peak / 1e6,
            peak / fit.rows as f64,
            match fit.memory_goal_met() {
                Some(met) => format!(" (goal <= 256 MB at 10 M rows: {})", verdict(met)),
                None => " (the goal, <= 256 MB, is at 10 M rows)".into(),
            }
        ),
        None => outln!("fit peak memory: not known here (read from /proc on Linux)"),
    }
    if let Some(peak) = fit.run_peak_bytes {
        outln!("run peak memory: {:.1} MB", peak / 1e6);
    }
}
