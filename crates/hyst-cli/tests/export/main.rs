//! `hyst export c|rust`: the generated files compile (C99 with -Wall -Wextra -Werror, C++), say
//! where they came from, and bad input (an unknown kind, a newer format version, a name that is
//! no C identifier or clashes with hyst.h's) gets a clear error and writes nothing.
//! scripts/test-firmware runs the generated code against `hyst run` on the host and under QEMU.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use hyst_test_support::cli::{stderr, Binary};
use hyst_test_support::files::repo;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

mod headers;
mod hostile;
mod inverse;
mod timed;
