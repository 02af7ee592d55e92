//! `hyst fmu` end to end: the archive's listing, modelDescription.xml (FMI 2.0 co-simulation,
//! the variables, capabilities and model structure of docs/fmu.md), resources/fmu.toml, the model
//! file packed byte for byte, and bad arguments that name the problem and leave no file behind.
//!
//! The FMU binary here is a stand-in (an ELF header and the FMI symbol names): `hyst fmu` copies
//! it byte for byte, and scripts/test-fmu runs the real one through FMPy.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Output;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{piezo, piezo_fit};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

mod archive;
mod arguments;
mod model;
mod operator;
mod packing;
