//! Build script: Embree 3 bindings by bindgen (feature `embree`) or the Embree 4 library to link
//! (feature `embree4`; its declarations are in src/accel/embree/ffi/), and the OpenImageIO C++
//! shim compiled into a shared library with cc's compiler (feature `oiio`). Each system library is found at its standard Debian
//! path, with an environment-variable override, and a missing one fails with what to install.
//!
//! Either Embree feature sets `cfg(embree)`, which the code outside src/accel/embree/ tests.

use std::env;
#[cfg(any(feature = "embree", feature = "embree4", feature = "oiio"))]
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo::rustc-check-cfg=cfg(embree)");
    let embree3 = env::var_os("CARGO_FEATURE_EMBREE").is_some();
    let embree4 = env::var_os("CARGO_FEATURE_EMBREE4").is_some();
    if embree3 && embree4 {
        fail(
            "features `embree` (Embree 3) and `embree4` are mutually exclusive (both libraries \
             export the same rtc* symbols): build with `--no-default-features --features embree4,oiio`",
        );
    }
    if embree3 || embree4 {
        println!("cargo:rustc-cfg=embree");
    }
    // OpenImageIO is not on the link line (its shim is loaded on first use), so Embree 4's own
    // oneTBB is in the global scope before the system oneTBB that OpenImageIO pulls in later:
    // both export the same unversioned symbols, and the loader binds the first.
    if embree3 {
        build_embree();
    }
    if embree4 {
        build_embree4();
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

/// Embree 4, found in this order: `EMBREE4_DIR` (a directory holding `libembree4.so`); a system
/// Embree ≥ 4.3 known to pkg-config as `embree4`; the copy scripts/install-embree4.sh unpacks
/// into target/embree4/lib. A directory is linked with an rpath to it, so the binaries, tests
/// and benches find the library (and, through its own `$ORIGIN` rpath, its oneTBB) at run time.
#[cfg(feature = "embree4")]
fn build_embree4() {
    println!("cargo:rerun-if-env-changed=EMBREE4_DIR");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let local = manifest.join("target/embree4/lib");
    let dir = if let Some(d) = env::var_os("EMBREE4_DIR") {
        PathBuf::from(d)
    } else if let Ok(lib) = pkg_config::Config::new().cargo_metadata(false).atleast_version("4.3").probe("embree4") {
        check_embree4_config(&lib.include_paths);
        for dir in &lib.link_paths {
            println!("cargo:rustc-link-search=native={}", dir.display());
        }
        println!("cargo:rustc-link-lib=dylib=embree4");
        return;
    } else {
        local
    };
    let lib = dir.join("libembree4.so");
    if !lib.exists() {
        fail(&format!(
            "feature `embree4` needs Embree 4: run `scripts/install-deps.sh --embree4` (or \
             scripts/install-embree4.sh), install a system Embree >= 4.3 with pkg-config file \
             embree4, or set EMBREE4_DIR to a directory holding libembree4.so (not found: {})",
            lib.display()
        ));
    }
    println!("cargo:rerun-if-changed={}", lib.display());
    println!("cargo:rustc-link-search=native={}", dir.display());
    println!("cargo:rustc-link-lib=dylib=embree4");
    println!("cargo:rustc-link-arg=-Wl,-rpath,{}", dir.display());
}

/// A system Embree 4's configuration must be the one src/accel/embree/ffi/embree4_api.rs
/// declares (one instance level, instance arrays), as its rtcore_config.h states it; the device
/// checks the library itself again at start-up.
#[cfg(feature = "embree4")]
fn check_embree4_config(include_paths: &[PathBuf]) {
    let config = include_paths
        .iter()
        .chain([PathBuf::from("/usr/include")].iter())
        .map(|d| d.join("embree4/rtcore_config.h"))
        .find(|p| p.exists());
    let Some(config) = config else {
        fail("pkg-config knows embree4 but embree4/rtcore_config.h is not in its include paths");
    };
    println!("cargo:rerun-if-changed={}", config.display());
    let text = std::fs::read_to_string(&config).unwrap_or_default();
    let defines = |name: &str, value: &str| {
        text.lines().any(|l| {
            let mut w = l.split_whitespace();
            w.next() == Some("#define") && w.next() == Some(name) && w.next().unwrap_or("") == value
        })
    };
    // The header defines RTC_GEOMETRY_INSTANCE_ARRAY under `#if defined(EMBREE_GEOMETRY_INSTANCE_ARRAY)`.
    if !defines("RTC_MAX_INSTANCE_LEVEL_COUNT", "1") || !defines("EMBREE_GEOMETRY_INSTANCE_ARRAY", "") {
        fail(&format!(
            "the system Embree 4 ({}) is configured with other than RTC_MAX_INSTANCE_LEVEL_COUNT 1 \
             and RTC_GEOMETRY_INSTANCE_ARRAY, whose hit layout prism declares: use \
             scripts/install-embree4.sh's copy (EMBREE4_DIR) instead",
            config.display()
        ));
    }
}

#[cfg(not(feature = "embree4"))]
fn build_embree4() {}

/// Ends the build script with a one-line error (cargo shows the script's stderr), never a panic.
#[allow(dead_code)]
fn fail(message: &str) -> ! {
    eprintln!("error: prism: {message}");
    std::process::exit(1);
}

/// Compiles `cpp/oiio_shim.cpp` (C++17) against the system OpenImageIO found by pkg-config into
/// the shared library `libprism_oiio_shim.so` in OUT_DIR, whose path the crate receives as
/// `PRISM_OIIO_SHIM`. prism loads it on first use rather than linking it: OpenImageIO brings ~260
/// shared libraries whose loading and relocation cost every process 0.26 s at start-up.
#[cfg(feature = "oiio")]
fn build_oiio() {
    println!("cargo:rerun-if-changed=cpp/oiio_shim.h");
    println!("cargo:rerun-if-changed=cpp/oiio_shim.cpp");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");

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
    build.cpp(true).std("c++17").pic(true).include("cpp").warnings(true).cargo_metadata(false);
    for dir in &oiio.include_paths {
        build.include(dir);
    }
    let compiler =
        build.try_get_compiler().unwrap_or_else(|e| fail(&format!("no C++ compiler for the OpenImageIO shim: {e}")));
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("libprism_oiio_shim.so");
    let mut cmd = compiler.to_command();
    cmd.args(["-shared", "-Wl,--no-undefined", "-o"]).arg(&out).arg("cpp/oiio_shim.cpp");
    for dir in &oiio.link_paths {
        cmd.arg(format!("-L{}", dir.display())).arg(format!("-Wl,-rpath,{}", dir.display()));
    }
    // pkg-config lists both OpenImageIO and OpenImageIO_Util; the shim needs both.
    let mut libs = oiio.libs.clone();
    for needed in ["OpenImageIO", "OpenImageIO_Util"] {
        if !libs.iter().any(|l| l == needed) {
            libs.push(needed.to_string());
        }
    }
    cmd.args(libs.iter().map(|l| format!("-l{l}")));
    match cmd.output() {
        Ok(o) if o.status.success() => {}
        Ok(o) => fail(&format!(
            "compiling the OpenImageIO shim failed: {}",
            String::from_utf8_lossy(&o.stderr).lines().find(|l| l.contains("error")).unwrap_or("(no message)")
        )),
        Err(e) => fail(&format!("cannot run the C++ compiler for the OpenImageIO shim: {e}")),
    }
    println!("cargo:rustc-env=PRISM_OIIO_SHIM={}", out.display());
}

#[cfg(not(feature = "oiio"))]
fn build_oiio() {}
