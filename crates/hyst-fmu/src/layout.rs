//! The layout of an FMU of hyst, shared by what writes the FMU ([`crate::description`], packed
//! by `hyst fmu`) and this binary (which reads it): the files of the resources folder, the format
//! and version of fmu.toml, and the value references and names of the variables (docs/fmu.md).

/// The configuration file's name in the resources folder.
pub const CONFIG_FILE: &str = "fmu.toml";
/// The model file's name in the resources folder (kind = "model").
pub const MODEL_FILE: &str = "model.toml";
/// `format` of fmu.toml.
pub const FORMAT: &str = "hyst-fmu";
/// The fmu.toml `version` that `hyst fmu` writes and this binary reads.
pub const VERSION: i64 = 1;

/// Value reference of x (Real, input): the operator's or the model's input, or the desired
/// output for an inverse.
pub const VR_X: u32 = 0;
/// Value reference of y (Real, output, direct feedthrough).
pub const VR_Y: u32 = 1;
/// Value reference of x_d1, the first time derivative of x: the inverse of a model with dynamics
/// of order n (Lemma 5.1's compensator) takes x_d1 … x_dn, value references 2 … n + 1, as
/// inputs (a model FMU has no k1, k2).
pub const VR_X_D1: u32 = 2;
/// The names of x's time derivatives x_d1 … x_d4 (the columns `<output>_d1` … of
/// `hyst run --model M --inverse`).
pub const DERIVATIVE_NAMES: [&str; hyst_model::MAX_DYNAMICS] = ["x_d1", "x_d2", "x_d3", "x_d4"];
/// Value reference of k1 (Real parameter, kind = "operator" only).
pub const VR_K1: u32 = 2;
/// Value reference of k2 (Real parameter, kind = "operator" only).
pub const VR_K2: u32 = 3;
