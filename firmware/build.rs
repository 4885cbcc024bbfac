//! Chooses the memory map: the top-level `memory.x` (MSP430FG439) or, with feature `fg4619-map`,
//! `memory-fg4619.x` (MSP430FG4619 / F2619; with `fg4619-map` but without `pil`, the flight
//! build, `memory-fg4619-node.x`, which keeps the element store's two segments free), with feature `large-map` `memory-large.x`, or with
//! feature `size-map` the measurement-only `memory-size.x`; copies it to OUT_DIR as `memory.x`,
//! where `link.x` includes it.
use std::{env, fs, path::PathBuf};

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    let map = if env::var_os("CARGO_FEATURE_SIZE_MAP").is_some() {
        manifest.join("memory-size.x")
    } else if env::var_os("CARGO_FEATURE_FG4619_MAP").is_some() {
        if env::var_os("CARGO_FEATURE_PIL").is_some() {
            manifest.join("memory-fg4619.x")
        } else {
            manifest.join("memory-fg4619-node.x")
        }
    } else if env::var_os("CARGO_FEATURE_LARGE_MAP").is_some() {
        manifest.join("memory-large.x")
    } else {
        manifest.join("../memory.x")
    };
    if let Err(e) = fs::copy(&map, out.join("memory.x")) {
        panic!("copying {}: {e}", map.display());
    }
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-search={}", manifest.display());
    println!("cargo:rerun-if-changed={}", map.display());
    println!("cargo:rerun-if-changed=link.x");
    println!("cargo:rerun-if-changed=memory-large.x");
    println!("cargo:rerun-if-changed=memory-size.x");
    println!("cargo:rerun-if-changed=memory-fg4619.x");
    println!("cargo:rerun-if-changed=memory-fg4619-node.x");
    println!("cargo:rerun-if-changed=../memory.x");
}
