//! `hyst-bench`: hyst's inverse operator against a plain-C peer of it (src/peer.c, no checks) on
//! the same signal, ns per sample, measured as `hyst bench` measures (interleaved rounds of
//! ~5 ms batches, the fastest batch of each kept), and the goal: hyst's inverse at most 1.0 ×
//! the peer (`cargo run --release -p hyst-bench -- --json`).

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hyst_bench::peer::{PeerComparison, C_PEER_GOAL};
use hyst_bench::workloads::{calibrate, measure, Suite as _};
use serde_json::json;

/// Times hyst's inverse operator against a plain-C peer on the same signal (ns per sample).
#[derive(Parser, Debug)]
#[command(name = "hyst-bench", version, about, long_about = None)]
struct Args {
    /// Print JSON (inverse_ns, c_peer_ns, inverse_over_c_peer and c_peer_goal_met) instead of a
    /// table.
    #[arg(long)]
    json: bool,
    /// Total measuring time of the whole run, in seconds, in (0, 60] (wall clock; the run takes
    /// this plus a little calibration).
    #[arg(long, default_value_t = 1.0)]
    seconds: f64,
}

fn main() -> ExitCode {
    let args = Args::parse();
    if !(args.seconds.is_finite() && args.seconds > 0.0 && args.seconds <= 60.0) {
        eprintln!("error: --seconds {}: must be in (0, 60]", args.seconds);
        return ExitCode::FAILURE;
    }
    let suite = PeerComparison::new();
    let names = suite.names();
    for (index, (name, _)) in names.iter().enumerate() {
        if !suite.run(index).is_finite() {
            eprintln!("error: benchmark workload {name:?} gave a non-finite checksum");
            return ExitCode::FAILURE;
        }
    }
    let calls = calibrate(&suite);
    let best = measure(&suite, &calls, Duration::from_secs_f64(args.seconds));
    let (inverse, peer) = (best.first(), best.get(1));
    let (Some(&inverse), Some(&peer)) = (inverse, peer) else {
        eprintln!("error: the workloads were not measured");
        return ExitCode::FAILURE;
    };
    let ratio = inverse / peer;
    let met = ratio <= C_PEER_GOAL;
    if args.json {
        let mut map = serde_json::Map::new();
        for ((_, key), ns) in names.iter().zip([inverse, peer]) {
            map.insert((*key).to_string(), json!(ns));
        }
        map.insert("inverse_over_c_peer".into(), json!(ratio));
        map.insert("c_peer_goal_met".into(), json!(met));
        match serde_json::to_string_pretty(&map) {
            Ok(text) => println!("{text}"),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        println!("{:<40} {:>10}", "workload", "ns/sample");
        for ((name, _), ns) in names.iter().zip([inverse, peer]) {
            println!("{name:<40} {ns:>10.2}");
        }
        println!();
        println!(
            "goal inverse <= {C_PEER_GOAL:.1} x plain-C peer:   {ratio:.2} ({})",
            if met { "met" } else { "NOT met" }
        );
    }
    ExitCode::SUCCESS
}
