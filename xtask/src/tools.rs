//! External importers CI runs the FMU through, installed on demand from the
//! package registries and cached in the work tree under `.tools/`.
//!
//! * `fmi-sim` (rust-fmi's command-line simulator, crates.io), pinned to
//!   [`FMI_SIM_VERSION`], installed with `cargo install --root
//!   .tools/fmi-sim-<version>`; an existing install is reused, so a CI cache of
//!   `.tools/` skips the build. Its build runs bindgen, which needs libclang:
//!   on Debian the package `libclang-dev` is installed with apt-get (through
//!   sudo only when not running as root). `cargo xtask test` builds it only
//!   when asked (`--fmi-sim`) and otherwise uses an existing install.
//! * Ecos (`ecospy`, a wheel from the Python registry pinned in
//!   tests/python/requirements.txt) links the system's oneTBB: Debian's
//!   `libtbb12` is installed with apt-get when missing.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{cargo, root, run, Result};

/// The fmi-sim release the importer comparison was verified with.
pub const FMI_SIM_VERSION: &str = "0.7.0";

/// Path of an installed `fmi-sim` executable of the pinned version, if any.
pub fn fmi_sim_installed() -> Option<PathBuf> {
    let exe = root().join(format!(".tools/fmi-sim-{FMI_SIM_VERSION}/bin/fmi-sim"));
    exe.exists().then_some(exe)
}

/// Path of the `fmi-sim` executable, installing it first if missing.
pub fn fmi_sim() -> Result<PathBuf> {
    let prefix = root().join(format!(".tools/fmi-sim-{FMI_SIM_VERSION}"));
    let exe = prefix.join("bin/fmi-sim");
    if exe.exists() {
        return Ok(exe);
    }
    ensure_libclang()?;
    // A debug build without debug info: fmi-sim only drives the FMU, whose
    // own code is the optimised part; this builds in about a third of the
    // CPU time of a release build.
    run(
        cargo()
            .env("CARGO_PROFILE_DEV_DEBUG", "false")
            .args(["install", "fmi-sim", "--locked", "--debug", "--version"])
            .arg(FMI_SIM_VERSION)
            .arg("--root")
            .arg(&prefix),
        "install fmi-sim",
    )?;
    if exe.exists() {
        Ok(exe)
    } else {
        Err(format!("cargo install did not produce {}", exe.display()))
    }
}

/// Whether bindgen will find libclang: `LIBCLANG_PATH` set, Debian's
/// `libclang-dev` installed (library and clang's headers), or, on systems
/// without dpkg, a libclang shared library where clang-sys looks for it.
fn libclang_found() -> bool {
    if std::env::var_os("LIBCLANG_PATH").is_some() {
        return true;
    }
    if let Ok(o) = Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", "libclang-dev"])
        .output()
    {
        return String::from_utf8_lossy(&o.stdout).contains("install ok installed");
    }
    let is_libclang = |p: &Path| {
        p.file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with("libclang") && n.contains(".so"))
    };
    let mut dirs = vec![
        PathBuf::from("/usr/lib/x86_64-linux-gnu"),
        PathBuf::from("/usr/lib/aarch64-linux-gnu"),
        PathBuf::from("/usr/lib64"),
        PathBuf::from("/usr/lib"),
    ];
    if let Ok(entries) = std::fs::read_dir("/usr/lib") {
        for e in entries.flatten() {
            if e.file_name().to_string_lossy().starts_with("llvm-") {
                dirs.push(e.path().join("lib"));
            }
        }
    }
    dirs.iter().any(|d| {
        std::fs::read_dir(d).is_ok_and(|mut it| {
            it.any(|e| {
                e.is_ok_and(|e| {
                    let name = e.file_name();
                    let name = name.to_string_lossy();
                    // libclang.so / libclang-14.so.1, not libclang-cpp.
                    is_libclang(&e.path()) && !name.starts_with("libclang-cpp")
                })
            })
        })
    })
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// `apt-get <args>`, through sudo unless already root.
fn apt_get(args: &[&str]) -> Command {
    let mut cmd = if is_root() {
        Command::new("apt-get")
    } else {
        let mut c = Command::new("sudo");
        c.arg("apt-get");
        c
    };
    cmd.env("DEBIAN_FRONTEND", "noninteractive").args(args);
    cmd
}

fn ensure_libclang() -> Result<()> {
    if libclang_found() {
        return Ok(());
    }
    apt_install("libclang-dev")
}

/// Whether the dynamic linker finds oneTBB's `libtbb.so.12` (Ecos needs it).
fn tbb_found() -> bool {
    Command::new("ldconfig")
        .arg("-p")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("libtbb.so.12"))
        || ["/usr/lib/x86_64-linux-gnu", "/usr/lib64", "/usr/lib"]
            .iter()
            .any(|d| Path::new(d).join("libtbb.so.12").exists())
}

/// Whether `libtbb12` is present (else [`ensure_tbb`] installs it).
pub fn tbb_present() -> bool {
    tbb_found()
}

/// Debian's `libtbb12` for the Ecos importer (ecospy's library links it).
pub fn ensure_tbb() -> Result<()> {
    if tbb_found() {
        return Ok(());
    }
    apt_install("libtbb12")
}

/// Debian's `chromium` for the browser tests of the FMU manual and the
/// animation (tests/python/test_browser.py), unless `BELTDRIVE_CHROMIUM`
/// names a browser or `chromium` is on the PATH.
pub fn ensure_chromium() -> Result<()> {
    if chromium_present() {
        return Ok(());
    }
    apt_install("chromium")
}

/// Whether a browser for the browser tests is there (else
/// [`ensure_chromium`] installs Debian's `chromium`).
pub fn chromium_present() -> bool {
    std::env::var_os("BELTDRIVE_CHROMIUM").is_some()
        || Command::new("chromium")
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
}

/// `apt-get install` one Debian package, updating the package lists first if
/// the install fails (a fresh machine may have empty lists).
fn apt_install(package: &str) -> Result<()> {
    let install = ["install", "-y", "-q", "--no-install-recommends", package];
    let what = format!("apt-get install {package}");
    if run(&mut apt_get(&install), &what).is_err() {
        run(&mut apt_get(&["update", "-q"]), "apt-get update")?;
        run(&mut apt_get(&install), &what)?;
    }
    Ok(())
}
