//! Build script: Embree 3 bindings by bindgen (feature `embree`) and the OpenImageIO C++ shim
//! compiled by cc (feature `oiio`). Each system library is found at its standard Debian path,
//! with an environment-variable override, and a missing one fails with the package to install.

use std::env;
#[cfg(feature = "embree")]
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if env::var_os("CARGO_FEATURE_EMBREE").is_some() {
        build_embree();
    }
    if env::var_os("CARGO_FEATURE_OIIO").is_some() {
        build_oiio();
    }
}

/// Embree 3 as Debian 12 ships it (`libembree-dev`, 3.13): no pkg-config file, so the include and
/// library directories come from `EMBREE_DIR` (a prefix with include/ and lib/) or the standard
/// paths. Everything version-specific (the header path, the library name) is here and in
/// src/accel/embree/, so an Embree 4 build is a contained change.
#[cfg(feature = "embree")]
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
        fail(&format!(
            "Embree 3 headers not found at {}: run scripts/install-deps.sh (or `apt-get install \
             libembree-dev`), set EMBREE_DIR to an Embree 3 prefix, or build without Embree \
             (`cargo build --no-default-features`)",
            header.display()
        ));
    }
    if let Some(lib) = lib_dir {
        println!("cargo:rustc-link-search=native={}", lib.display());
    }
    println!("cargo:rustc-link-lib=dylib=embree3");
    println!("cargo:rerun-if-changed={}", header.display());

    let builder = bindgen::Builder::default()
        .header(header.to_string_lossy())
        .clang_arg(format!("-I{}", include_dir.display()))
        .allowlist_function("rtc.*")
        .allowlist_type("RTC.*")
        .allowlist_var("RTC.*")
        .default_enum_style(bindgen::EnumVariation::Consts)
        .derive_default(true)
        .layout_tests(false);
    let bindings = generate_bindings(builder, &header);
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("embree3_bindings.rs");
    if let Err(e) = bindings.write_to_file(&out) {
        fail(&format!("cannot write the Embree bindings to {}: {e}", out.display()));
    }
}

/// Runs bindgen. bindgen panics when it cannot load libclang (clang-sys's loader is `expect`ed
/// inside it); that panic is caught with the default hook silenced, so a missing libclang is one
/// line naming the package, not a backtrace.
#[cfg(feature = "embree")]
fn generate_bindings(builder: bindgen::Builder, header: &std::path::Path) -> bindgen::Bindings {
    println!("cargo:rerun-if-env-changed=LIBCLANG_PATH");
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    std::panic::set_hook(hook);
    match result {
        Ok(Ok(bindings)) => bindings,
        Ok(Err(e)) => fail(&format!("bindgen failed on {}: {e}", header.display())),
        Err(_) => fail(
            "bindgen cannot load libclang: run scripts/install-deps.sh (or `apt-get install \
             libclang-dev`), or set LIBCLANG_PATH to the directory holding libclang.so",
        ),
    }
}

#[cfg(not(feature = "embree"))]
fn build_embree() {}

/// Ends the build script with a one-line error (cargo shows the script's stderr), never a panic.
#[allow(dead_code)]
fn fail(message: &str) -> ! {
    eprintln!("error: prism: {message}");
    std::process::exit(1);
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
    let oiio = match pkg_config::Config::new().cargo_metadata(false).probe("OpenImageIO") {
        Ok(lib) => lib,
        Err(e) => fail(&format!(
            "feature `oiio` needs OpenImageIO: run scripts/install-deps.sh (or `apt-get install \
             libopenimageio-dev`), or build with `--no-default-features` for the pure-Rust image \
             path (pkg-config: {})",
            e.to_string().lines().next().unwrap_or_default()
        )),
    };

    let mut build = cc::Build::new();
    build.cpp(true).std("c++17").file("cpp/oiio_shim.cpp").include("cpp").warnings(true);
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
