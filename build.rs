//! Build script: Embree 3 bindings by bindgen (feature `embree`) and the OpenImageIO C++ shim
//! compiled by cc (feature `oiio`). Each system library is found at its standard Debian path,
//! with an environment-variable override, and a missing one fails with the package to install.

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if env::var_os("CARGO_FEATURE_EMBREE").is_some() {
        build_embree();
    }
}

/// Embree 3 as Debian 12 ships it (`libembree-dev`, 3.13): no pkg-config file, so the include and
/// library directories come from `EMBREE_DIR` (a prefix with include/ and lib/) or the standard
/// paths. Everything version-specific (the header path, the library name) is here and in
/// src/accel/embree/, so an Embree 4 build is a contained change.
fn build_embree() {
    println!("cargo:rerun-if-env-changed=EMBREE_DIR");
    let (include_dir, lib_dir) = match env::var_os("EMBREE_DIR") {
        Some(prefix) => {
            let p = PathBuf::from(prefix);
            (p.join("include"), Some(p.join("lib")))
        }
        None => (PathBuf::from("/usr/include"), None),
    };
    let header = include_dir.join("embree3/rtcore.h");
    if !header.exists() {
        panic!(
            "\n\nprism: Embree 3 headers not found at {}.\n\
             Install them with `apt-get install libembree-dev` (Debian 12), set EMBREE_DIR to an\n\
             Embree 3 install prefix, or build without Embree: `cargo build --no-default-features`.\n",
            header.display()
        );
    }
    if let Some(lib) = lib_dir {
        println!("cargo:rustc-link-search=native={}", lib.display());
    }
    println!("cargo:rustc-link-lib=dylib=embree3");
    println!("cargo:rerun-if-changed={}", header.display());

    let bindings = bindgen::Builder::default()
        .header(header.to_string_lossy())
        .clang_arg(format!("-I{}", include_dir.display()))
        .allowlist_function("rtc.*")
        .allowlist_type("RTC.*")
        .allowlist_var("RTC.*")
        .default_enum_style(bindgen::EnumVariation::Consts)
        .derive_default(true)
        .layout_tests(false)
        .generate()
        .unwrap_or_else(|e| {
            panic!("prism: bindgen failed on {} ({e}); is libclang-dev installed?", header.display())
        });
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("embree3_bindings.rs");
    bindings.write_to_file(&out).expect("write Embree bindings");
}
