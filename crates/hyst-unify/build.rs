//! Empty: cargo resolves `[build-dependencies]` (syn, for the host's proc-macros) only for a
//! package with a build script.

fn main() {}
