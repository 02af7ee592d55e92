//! The exported models (`hyst export rust`) in a `no_std` library, as a firmware crate holds
//! them: `include!`d from `$HYST_EXPORT_DIR` (scripts/test-firmware writes them there), built
//! in `f32` and `f64`.
#![no_std]

include!(concat!(env!("HYST_EXPORT_DIR"), "/piezo.rs"));
include!(concat!(env!("HYST_EXPORT_DIR"), "/steel.rs"));
include!(concat!(env!("HYST_EXPORT_DIR"), "/friction.rs"));
include!(concat!(env!("HYST_EXPORT_DIR"), "/piezo_pi.rs"));
include!(concat!(env!("HYST_EXPORT_DIR"), "/piezo_dyn.rs"));

use hyst_core::Operator;

/// One step of every exported model and inverse, in `T`: what a control loop's tick does (and
/// what makes the compiler build every constructor for the target).
///
/// # Errors
/// A constructor's or a step's error.
pub fn tick<T: hyst_core::Real>(x: T, desired: T) -> Result<[T; 8], hyst_core::Error> {
    let mut model = piezo::<T>()?;
    let mut inverse = piezo_inverse::<T>()?;
    let mut magnet = steel_inverse::<T>()?;
    let mut stop = friction::<T>()?;
    let mut pi = piezo_pi::<T>()?;
    let mut pi_inverse = piezo_pi_inverse::<T>()?;
    // A model with dynamics: its compensator (the desired output at rest) and its model with
    // the plant.
    let mut compensator = piezo_dyn_timed_compensator::<T>(desired)?;
    let mut timed = piezo_dyn_timed::<T>()?;
    let at_rest = [desired, T::zero(), T::zero()];
    Ok([
        model.try_step(x)?,
        inverse.try_step(desired)?,
        magnet.try_step(steel_clamp(desired))?,
        stop.try_step(x)?,
        pi.try_step(x)?,
        pi_inverse.try_step(desired)?,
        compensator.track(piezo_dyn_reference(&at_rest))?,
        timed.try_step(x)?,
    ])
}

/// The `f32` build a Cortex-M4F runs.
///
/// # Errors
/// As [`tick`].
pub fn tick_f32(x: f32, desired: f32) -> Result<[f32; 8], hyst_core::Error> {
    tick(x, desired)
}

/// The `f64` build.
///
/// # Errors
/// As [`tick`].
pub fn tick_f64(x: f64, desired: f64) -> Result<[f64; 8], hyst_core::Error> {
    tick(x, desired)
}
