//! No code. A dependency of every crate that is built in release on its own (hyst-cli,
//! hyst-capi with `std`, hyst-py, hyst-bench), which gives the dependencies they share one
//! feature set in all those builds (Cargo.toml lists it), so that each build reuses most of what
//! the others compiled.
#![no_std]
#![forbid(unsafe_code)]
