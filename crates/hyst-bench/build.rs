//! Build script of hyst-bench: compiles the plain-C peer of the inverse operator (src/peer.c)
//! that `hyst-bench` and the criterion benches measure hyst against, with the `cc` crate at -O2.
//! It lives here, not in hyst-cli, so the `hyst` executable compiles and links no C.

/// Compiles src/peer.c into a static library linked into this crate: -O2, no fused
/// multiply-adds (Rust makes none, so the peer computes what hyst computes), the platform's libm
/// for `exp`.
fn main() {
    println!("cargo:rerun-if-changed=src/peer.c");
    cc::Build::new()
        .file("src/peer.c")
        .opt_level(2)
        .flag_if_supported("-ffp-contract=off")
        .warnings(true)
        .compile("hyst_peer");
    if std::env::var("CARGO_CFG_TARGET_FAMILY").as_deref() == Ok("unix")
        && std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("macos")
    {
        println!("cargo:rustc-link-lib=m");
    }
}
