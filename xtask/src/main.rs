//! Project tasks: `cargo xtask <fmu|venv|run|validate|crosscheck|fmi-sim|test|valgrind|bench>`.
//!
//! * `fmu`  - release build, then `dist/BeltDrive.fmu` (model description with
//!   its GUID, the Linux binary, generated documentation, model icon).
//! * `venv` - `.venv` with the Python test harness (FMPy, pytest, ...).
//! * `setup [--no-browser]` - `venv` and the Debian packages the Python
//!   tests need (`libtbb12`, `chromium`).
//! * `run [-- --fast --stop-time T]` - the main job: build the FMU and
//!   simulate its default drive through FMPy with RKF45 and the stiff method
//!   side by side (`--fast`: the stiff method only); a report of both with
//!   their times, `dist/default_drive.png`, the animation
//!   `dist/default_drive.html` (with `dist/default_drive_frames.json`) and
//!   the report's figures `dist/default_drive.json`.
//! * `crosscheck` - reference results in the FMI cross-check layout beside
//!   the FMU: `dist/BeltDrive_{ref.csv,ref.opt,in.csv}` (FMPy).
//! * `fmi-sim` - install the pinned rust-fmi `fmi-sim` into `.tools/`.
//! * `test [--fmi-sim] [--no-browser]` - everything CI runs: fmt, clippy,
//!   cargo tests, valgrind (if installed), FMU, cross-check files, pytest
//!   (FMPy, the other importers, the browser tests, fmi-sim if installed).
//! * `valgrind` - memcheck over instantiate / step / FMU-state / free cycles
//!   of the built library (`examples/valgrind_driver.rs`).
//! * `validate` - the validation report: both paper drives, the closed-form
//!   panel and the convergence studies through the built FMU
//!   (`validation/validate.py`; plots in `docs/validation/`, tables in
//!   `docs/validation.md` and `docs/model.md`). Arguments after `--` go to
//!   the script (`--quick --out DIR`, `--method`, `--dv`, `--jobs`, ...).
//! * `bench [--full] [--quick] [--core N] [--no-docs]` - the benchmark suites
//!   (`benches/belt.rs`, `benches/stiff.rs`); rewrites the generated part of
//!   `docs/benchmarks.md` (see `bench.rs`).
//! * `model-description` - writes `modelDescription/modelDescription.xml`
//!   from the registry (`modelDescription/src/registry/table.rs`).
//! * `modes -- [--ssv FILE] [--set NAME=VALUE ...] [--speeds FROM:TO:N] [--at TIME] [--range LO:HI]
//!   [--arm-amplitude DEG] [--idle-loads] [--mesh-check BODIES]`:
//!   the modal analysis (`examples/modes.rs`), `dist/modes.csv` and, with
//!   `--speeds`, the Campbell diagram `dist/campbell.png` (docs/modes.md).
//! * `layout -- [--ssv FILE] [--set NAME=VALUE ...] [--names A,B,...] [--out FILE.svg]`:
//!   a drawing of the mounted drive, `dist/layout.svg` and `dist/layout.png`
//!   (`examples/layout.rs`, docs/layout.md).

mod bench;
mod docs;
mod drawing;
#[cfg(test)]
mod hygiene;
mod icon;
mod tools;

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{exit, Command};

type Result<T> = std::result::Result<T, String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

fn run(cmd: &mut Command, what: &str) -> Result<()> {
    eprintln!("xtask: {what}: {cmd:?}");
    let status = cmd
        .current_dir(root())
        .status()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what} failed ({status})"))
    }
}

/// [`run`], printing a line every 15 s while `cmd` runs: for the builds,
/// whose final fat-LTO link is silent for a minute or more.
fn run_with_heartbeat(cmd: &mut Command, what: &str) -> Result<()> {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};
    let done = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&done);
    let label = what.to_string();
    let t0 = Instant::now();
    let beat = std::thread::spawn(move || {
        let mut next = 15;
        while !flag.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(200));
            let s = t0.elapsed().as_secs();
            if s >= next {
                eprintln!("xtask: {label}: still running ({s} s)");
                next += 15;
            }
        }
    });
    let result = run(cmd, what);
    done.store(true, Ordering::Relaxed);
    let _ = beat.join();
    result
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
}

/// The Cargo package (and library) that is the FMU's binary.
const FMU_PACKAGE: &str = "belt_drive";

fn fmu() -> Result<PathBuf> {
    run_with_heartbeat(
        cargo().args(["build", "--release", "--lib", "-p", FMU_PACKAGE]),
        "release build of the FMU's library",
    )?;
    let root = root();
    let source = fs::read_to_string(root.join("modelDescription/modelDescription.xml"))
        .map_err(|e| format!("reading the model description: {e}"))?;
    // The same code build.rs runs: the same checks, the same GUID.
    let md = model_description::compile(&source)
        .map_err(|e| format!("modelDescription/modelDescription.xml: {e}"))?;
    let id = md.model_identifier();
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root.join("target"));
    let library = target.join("release").join(format!(
        "{}{FMU_PACKAGE}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ));
    let so = fs::read(&library).map_err(|e| format!("reading {}: {e}", library.display()))?;
    // The binary compares the importer's GUID with the one build.rs computed
    // from the same source: make sure the archive gets that very GUID.
    let guid = &md.guid;
    if !so.windows(guid.len()).any(|w| w == guid.as_bytes()) {
        return Err(format!(
            "the built library does not contain GUID {guid} of modelDescription.xml: stale build?"
        ));
    }
    let binary = model_description::platform::host_binary_path(id)?;
    let dist = root.join("dist");
    fs::create_dir_all(&dist).map_err(|e| e.to_string())?;
    let path = dist.join(format!("{id}.fmu"));
    let file = fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, bytes: &[u8]| -> Result<()> {
        zip.start_file(name, opts).map_err(|e| e.to_string())?;
        zip.write_all(bytes).map_err(|e| e.to_string())
    };
    let xml = &md.xml;
    add("modelDescription.xml", xml.as_bytes())?;
    add(&binary, &so)?;
    let manual = fs::read_to_string(root.join("docs/fmu-manual.md"))
        .map_err(|e| format!("reading docs/fmu-manual.md: {e}"))?;
    for (name, bytes) in docs::documentation(xml, &manual, &root.join("docs"))? {
        add(&format!("documentation/{name}"), &bytes)?;
    }
    add("model.png", &icon::model_png())?;
    zip.finish().map_err(|e| e.to_string())?;
    println!("{}", path.display());
    Ok(path)
}

fn venv_python() -> PathBuf {
    root().join(".venv/bin/python")
}

fn venv() -> Result<()> {
    let root = root();
    let reqs = root.join("tests/python/requirements.txt");
    let text = fs::read_to_string(&reqs).map_err(|e| format!("{}: {e}", reqs.display()))?;
    let stamp = root.join(".venv/.requirements");
    if venv_python().exists() && fs::read_to_string(&stamp).ok().as_deref() == Some(&text) {
        return Ok(());
    }
    if !venv_python().exists() {
        let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        run(
            Command::new(python).args(["-m", "venv", ".venv"]),
            "create .venv",
        )?;
    }
    let n = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .count();
    eprintln!(
        "xtask: installing the Python harness into .venv: {n} pinned packages \
         (tests/python/requirements.txt; first run only, 1-3 min depending on the network)"
    );
    run(
        Command::new(venv_python())
            .args(["-m", "pip", "install", "--progress-bar", "off", "-r"])
            .arg(&reqs),
        "install the Python harness",
    )?;
    fs::write(stamp, text).map_err(|e| e.to_string())
}

fn main_job(args: &[String]) -> Result<()> {
    // `cargo xtask run -- --stop-time 0.5`: drop the separator.
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    eprintln!(
        "cargo xtask run: the FMU's default drive, simulated with both integrators\n\
         \x20 1/3 build dist/BeltDrive.fmu and the belt-shape example (release builds: 1-3 min on a \
         fresh clone, seconds after that)\n\
         \x20 2/3 the Python environment .venv (FMPy and the plotting; 1-3 min on the first run only)\n\
         \x20 3/3 simulate with RKF45, then with the stiff method (`-- --fast`: the stiff method only), and report"
    );
    eprintln!("xtask: 1/3 building");
    fmu()?;
    // The animation's belt shape: the physics core with the FMU's defaults
    // (the FMU has no body position outputs), see examples/belt_shape.rs.
    run_with_heartbeat(
        cargo().args([
            "build",
            "--release",
            "--example",
            "belt_shape",
            "-p",
            "belt_drive",
        ]),
        "release build of the belt-shape example (animation)",
    )?;
    eprintln!("xtask: 2/3 the Python environment");
    venv()?;
    eprintln!("xtask: 3/3 simulating");
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root().join("target"));
    run(
        Command::new(venv_python())
            .arg("tests/python/run_default.py")
            .arg("--shape-exe")
            .arg(target.join("release/examples/belt_shape"))
            .args(args),
        "simulate the default drive",
    )
}

/// `cargo xtask crosscheck [-- --stop-time 0.5]`
fn crosscheck(args: &[String]) -> Result<()> {
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    fmu()?;
    venv()?;
    run(
        Command::new(venv_python())
            .arg("tests/python/crosscheck.py")
            .args(args),
        "cross-check reference results (FMPy)",
    )
}

/// `cargo xtask validate [-- --quick --out DIR ...]`
fn validate(args: &[String]) -> Result<()> {
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    fmu()?;
    venv()?;
    run(
        Command::new(venv_python())
            .arg("validation/validate.py")
            .args(args),
        "validation report",
    )
}

/// `cargo xtask sweep -- STUDY.toml [--scheduler ADDR] [--workers N] ...`:
/// a parameter study on Dask (python/beltdrive, docs/sweeps.md).
fn sweep(args: &[String]) -> Result<()> {
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    fmu()?;
    venv()?;
    run(
        Command::new(venv_python())
            .args(["-m", "beltdrive.sweep"])
            .args(args)
            .env("PYTHONPATH", root().join("python")),
        "parameter study",
    )
}

/// `cargo xtask test [--fmi-sim] [--no-browser]`: everything CI runs. It
/// first says what it will run and which Debian packages it will install
/// (`libtbb12` for Ecos, `chromium` for the browser tests; `--no-browser`
/// leaves the browser tests and chromium out, and pytest lists them as
/// skipped with the reason). The Rust tests build with the `ci` profile
/// (release optimisation without fat LTO, see Cargo.toml); the FMU the
/// Python tests load is the packaged release build. pytest prints every
/// skip with its reason.
/// rust-fmi's fmi-sim builds from source (about 5 min of CPU time), so it
/// runs only with `--fmi-sim` or when `.tools/` already holds it.
fn test(args: &[String]) -> Result<()> {
    let with_fmi_sim = args.iter().any(|a| a == "--fmi-sim");
    let browser = !args.iter().any(|a| a == "--no-browser");
    if let Some(bad) = args
        .iter()
        .find(|a| !matches!(a.as_str(), "--fmi-sim" | "--no-browser" | "--"))
    {
        return Err(format!(
            "test: unknown option {bad} (known: --fmi-sim, --no-browser)"
        ));
    }
    let valgrind = have_valgrind();
    let fmi_sim = tools::fmi_sim_installed();
    let state = |present: bool| {
        if present {
            "present"
        } else {
            "missing: will be installed with apt-get (through sudo when not root)"
        }
    };
    eprintln!(
        "cargo xtask test: everything CI runs\n\
         \x20 1. cargo fmt --check and cargo clippy -D warnings\n\
         \x20 2. the Rust tests ({}, profile ci, features modes)\n\
         \x20 3. valgrind memcheck of the C API: {}\n\
         \x20 4. the packaged FMU (release build) and its cross-check files\n\
         \x20 5. pytest: the FMU through FMPy, libcosim, Ecos, fmu-manipulation-toolbox, \
         the browser ({}) and fmi-sim ({})\n\
         System packages it needs (Debian):\n\
         \x20 libtbb12  the Ecos importer's library: {}\n\
         \x20 chromium  headless browser for the FMU manual and the animation page: {}",
        if nextest() {
            "cargo nextest, every test in its own process on all cores"
        } else {
            "cargo test; cargo-nextest would run them on all cores"
        },
        if valgrind {
            "valgrind found"
        } else {
            "valgrind not installed: skipped"
        },
        if browser {
            "on; --no-browser leaves it out"
        } else {
            "off: --no-browser"
        },
        match (&fmi_sim, with_fmi_sim) {
            (Some(_), _) => "installed in .tools/",
            (None, true) => "--fmi-sim: built now, about 5 min",
            (None, false) => "not installed: skipped; --fmi-sim builds it",
        },
        state(tools::tbb_present()),
        if browser {
            state(tools::chromium_present())
        } else {
            "not needed (--no-browser)"
        },
    );
    // The Python harness and the system packages download while cargo
    // builds: a child `cargo xtask setup` writes to a log file, so its output
    // does not interleave with the builds'.
    let setup = Setup::start(browser)?;
    run(
        cargo().args(["fmt", "--all", "--", "--check"]),
        "cargo fmt --check",
    )?;
    run(
        cargo().args([
            "clippy",
            "--workspace",
            "--all-targets",
            "--features",
            "belt_drive/modes",
            "--",
            "-D",
            "warnings",
        ]),
        "cargo clippy",
    )?;
    rust_tests()?;
    if valgrind {
        // The packages and features of the test build: nothing is built
        // again (`-p belt_drive` resolves the dependencies' features apart
        // from the workspace and compiled 21 crates a second time).
        valgrind_with("ci", &["--workspace", "--features", "belt_drive/modes"])?;
    } else {
        eprintln!("xtask: valgrind not found: skipping the memory check (cargo xtask valgrind)");
    }
    fmu()?;
    setup.finish()?;
    crosscheck(&[])?;
    let mut pytest = Command::new(venv_python());
    if !browser {
        pytest.env("BELTDRIVE_NO_BROWSER", "1");
    }
    // -rs: every skipped test with its reason in the summary; --durations:
    // the ten slowest tests, where the suite's time goes. One process:
    // the whole Python suite takes about 2.5 min, and under pytest-xdist a
    // worker died (SIGILL inside fmi2DoStep) and the run hung.
    pytest.args([
        "-m",
        "pytest",
        "-q",
        "-rs",
        "--durations=10",
        "-p",
        "no:cacheprovider",
        "tests/python",
    ]);
    let fmi_sim = if with_fmi_sim {
        Some(tools::fmi_sim()?)
    } else {
        fmi_sim
    };
    match fmi_sim {
        Some(exe) => {
            pytest.env("FMI_SIM", exe);
        }
        None => eprintln!(
            "xtask: fmi-sim not installed: its importer tests are skipped \
             (`cargo xtask test --fmi-sim` builds it into .tools/, about 5 min)"
        ),
    }
    run(
        &mut pytest,
        "pytest (the packaged FMU through FMPy and the other importers)",
    )
}

/// Whether `cargo nextest` can be started.
fn nextest() -> bool {
    cargo()
        .args(["nextest", "--version"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The Rust tests of the workspace with the `ci` profile and the `modes`
/// feature. With cargo-nextest (on the CI machines) every test runs in its
/// own process and the two cores stay busy; `cargo test` runs one test
/// binary after the other, so a binary's one long test leaves a core idle.
/// nextest does not run doctests: `cargo test --doc` runs them.
fn rust_tests() -> Result<()> {
    let common = ["--workspace", "--features", "belt_drive/modes"];
    if !nextest() {
        return run(
            cargo().args(["test", "--profile", "ci"]).args(common),
            "cargo test (profile ci)",
        );
    }
    run(
        cargo()
            .args(["nextest", "run", "--cargo-profile", "ci", "--no-fail-fast"])
            .args(common),
        "cargo nextest (profile ci)",
    )?;
    run(
        cargo()
            .args(["test", "--doc", "--profile", "ci"])
            .args(common),
        "doctests (profile ci)",
    )
}

/// `cargo xtask setup [--no-browser]`: the Python harness in `.venv` and
/// the Debian packages the Python tests need (`libtbb12`; `chromium` unless
/// `--no-browser`).
fn setup(args: &[String]) -> Result<()> {
    venv()?;
    tools::ensure_tbb()?;
    if !args.iter().any(|a| a == "--no-browser") {
        tools::ensure_chromium()?;
    }
    Ok(())
}

/// [`setup`] in a child process whose output goes to `target/setup.log`.
struct Setup {
    child: std::process::Child,
    log: PathBuf,
}

impl Setup {
    fn start(browser: bool) -> Result<Self> {
        let target = std::env::var("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|_| root().join("target"));
        fs::create_dir_all(&target).map_err(|e| format!("{}: {e}", target.display()))?;
        let log = target.join("setup.log");
        let file = fs::File::create(&log).map_err(|e| format!("{}: {e}", log.display()))?;
        let err = file.try_clone().map_err(|e| e.to_string())?;
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let mut cmd = Command::new(exe);
        cmd.arg("setup");
        if !browser {
            cmd.arg("--no-browser");
        }
        let child = cmd
            .current_dir(root())
            .stdout(file)
            .stderr(err)
            .spawn()
            .map_err(|e| format!("cargo xtask setup: cannot start: {e}"))?;
        eprintln!(
            "xtask: installing the Python harness and the system packages in the background \
             (log: {})",
            log.display()
        );
        Ok(Self { child, log })
    }

    /// Waits for the setup; on failure prints its log.
    fn finish(mut self) -> Result<()> {
        let status = self.child.wait().map_err(|e| e.to_string())?;
        let text = fs::read_to_string(&self.log).unwrap_or_default();
        if status.success() {
            eprintln!(
                "xtask: setup done ({} lines in {})",
                text.lines().count(),
                self.log.display()
            );
            return Ok(());
        }
        eprintln!("{text}");
        Err(format!(
            "setup of the Python harness failed ({status}); log above"
        ))
    }
}

/// `cargo xtask modes -- [--ssv FILE] [--set NAME=VALUE ...] [--speeds FROM:TO:N]
/// [--at TIME] [--fmax HZ] [--out FILE] [--frozen] [--arm-amplitude DEG] [--idle-loads]
/// [--mesh-check BODIES] [--range LO:HI]`: the modal analysis
/// (`examples/modes.rs`, which takes every option but `--range`) writes the
/// CSV (default `dist/modes.csv`); with
/// `--speeds` the Campbell diagram is drawn beside it (`campbell.png`, by
/// `examples/campbell.py` with matplotlib from `.venv`).
fn modes(args: &[String]) -> Result<()> {
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    // `--range LO:HI` is the Campbell diagram's frequency axis, not the
    // analysis': it goes to examples/campbell.py.
    let mut analysis = Vec::new();
    let mut range = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == "--range" {
            range = Some(
                it.next()
                    .ok_or("--range needs LO:HI (the Campbell diagram's frequency axis, Hz)")?
                    .clone(),
            );
        } else {
            analysis.push(a.clone());
        }
    }
    let args = &analysis[..];
    run(
        cargo()
            .args([
                "run",
                "--release",
                "--features",
                "modes",
                "--example",
                "modes",
                "--",
            ])
            .args(args),
        "modal analysis",
    )?;
    let csv = args
        .iter()
        .position(|a| a == "--out")
        .and_then(|i| args.get(i + 1))
        .map_or_else(|| PathBuf::from("dist/modes.csv"), PathBuf::from);
    if !args.iter().any(|a| a == "--speeds") {
        eprintln!("xtask: no --speeds: one linearisation, no Campbell diagram");
        return Ok(());
    }
    let png = if csv.file_name().is_some_and(|n| n == "modes.csv") {
        csv.with_file_name("campbell.png")
    } else {
        csv.with_extension("png")
    };
    venv()?;
    let mut plot = Command::new(venv_python());
    plot.arg("examples/campbell.py").arg(&csv).arg(&png);
    if let Some(r) = range {
        plot.args(["--range", &r]);
    }
    run(&mut plot, "Campbell diagram")
}

/// Whether `valgrind` can be started.
fn have_valgrind() -> bool {
    Command::new("valgrind")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// valgrind memcheck over the FMU library: `examples/valgrind_driver.rs`
/// loads it with dlopen and runs instantiate / step / FMU-state / free
/// cycles. Fails on any memcheck error or a definite or indirect leak
/// ("possibly lost" and "still reachable" blocks of the Rust runtime and of
/// dlopen are not errors).
fn valgrind() -> Result<()> {
    valgrind_with("release", &["-p", "belt_drive"])
}

/// [`valgrind`] on the build of the given cargo profile, of the packages
/// and features `select` names (cargo arguments).
fn valgrind_with(profile: &str, select: &[&str]) -> Result<()> {
    run(
        cargo()
            .args([
                "build",
                "--profile",
                profile,
                "--lib",
                "--example",
                "valgrind_driver",
            ])
            .args(select),
        "build of the library and the valgrind driver",
    )?;
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root().join("target"));
    run(
        Command::new("valgrind")
            .args([
                "--tool=memcheck",
                "--leak-check=full",
                "--errors-for-leak-kinds=definite,indirect",
                "--error-exitcode=1",
            ])
            .arg(target.join(profile).join("examples/valgrind_driver")),
        "valgrind memcheck",
    )
}

/// Writes `modelDescription/modelDescription.xml` from the registry
/// (`modelDescription/src/registry/table.rs`), after checking it.
fn model_description() -> Result<()> {
    let text = model_description::registry::model_description();
    model_description::compile(&text)?;
    let path = root().join("modelDescription/modelDescription.xml");
    fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("xtask: wrote {}", path.display());
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("fmu") => fmu().map(|_| ()),
        Some("venv") => venv(),
        Some("setup") => setup(&args[1..]),
        Some("run") => main_job(&args[1..]),
        Some("validate") => validate(&args[1..]),
        Some("crosscheck") => crosscheck(&args[1..]),
        Some("fmi-sim") => tools::fmi_sim().map(|p| println!("{}", p.display())),
        Some("test") => test(&args[1..]),
        Some("valgrind") => valgrind(),
        Some("bench") => bench::bench(&args[1..]),
        Some("modes") => modes(&args[1..]),
        Some("sweep") => sweep(&args[1..]),
        Some("model-description") => model_description(),
        Some("layout") => drawing::layout(&args[1..]).map(|_| ()),
        _ => Err(
            "usage: cargo xtask <fmu|venv|setup|run|validate|crosscheck|fmi-sim|test|valgrind|bench|sweep|modes|model-description|layout>"
                .into(),
        ),
    };
    if let Err(e) = result {
        eprintln!("xtask: {e}");
        exit(1);
    }
}
