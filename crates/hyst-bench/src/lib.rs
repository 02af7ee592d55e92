//! The benchmarks of hyst, apart from the `hyst` executable (which compiles and links no C):
//!
//! - [`workloads`]: the workloads `hyst bench` measures and how it measures them; hyst-cli
//!   compiles the same file as its module `workloads`, so both report the same thing;
//! - [`peer`]: the plain-C peer of the inverse operator (src/peer.c, compiled by build.rs with
//!   the `cc` crate) and [`peer::PeerComparison`], hyst's inverse next to it, which the
//!   `hyst-bench` binary times (`inverse_over_c_peer`, goal ≤ 1.0);
//! - the criterion benches: `cargo bench -p hyst-bench --bench operators` (every workload and
//!   the peer) and `--bench fit` (the fit's speed goals).

pub mod peer;
pub mod workloads;
