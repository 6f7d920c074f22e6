//! Build script: native pieces behind cargo features.
//!
//! Each native dependency has its own `build_*` function, called from `main` only when its
//! feature is enabled, so the pure-Rust build (`--no-default-features`) needs no system library.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_OIIO").is_some() {
        build_oiio();
    }
}

/// Compiles `cpp/oiio_shim.cpp` (C++17) against the system OpenImageIO found by pkg-config and
/// links it together with `OpenImageIO` and `OpenImageIO_Util`.
#[cfg(feature = "oiio")]
fn build_oiio() {
    println!("cargo:rerun-if-changed=cpp/oiio_shim.h");
    println!("cargo:rerun-if-changed=cpp/oiio_shim.cpp");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");

    // Probe without emitting link lines yet: the shim's static library must come before the
    // OIIO shared libraries on the link line, or the linker drops them as unneeded.
    let oiio = match pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("OpenImageIO")
    {
        Ok(lib) => lib,
        Err(e) => panic!(
            "feature `oiio` needs OpenImageIO: install `libopenimageio-dev` (Debian/Ubuntu) \
             or build with `--no-default-features` for the pure-Rust image path.\n\
             pkg-config said: {e}"
        ),
    };

    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        .file("cpp/oiio_shim.cpp")
        .include("cpp")
        .warnings(true);
    for dir in &oiio.include_paths {
        build.include(dir);
    }
    build.compile("prism_oiio_shim");

    for dir in &oiio.link_paths {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    // pkg-config lists both OpenImageIO and OpenImageIO_Util; the shim needs both.
    let mut libs = oiio.libs.clone();
    for needed in ["OpenImageIO", "OpenImageIO_Util"] {
        if !libs.iter().any(|l| l == needed) {
            libs.push(needed.to_string());
        }
    }
    for lib in libs {
        println!("cargo:rustc-link-lib={lib}");
    }
}

#[cfg(not(feature = "oiio"))]
fn build_oiio() {}
