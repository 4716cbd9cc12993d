//! `cargo xtask bench [--full] [--quick] [--core N]`: runs the benchmark
//! suites and rewrites the generated part of `docs/benchmarks.md`, the text
//! between `<!-- bench:begin -->` and `<!-- bench:end -->`, with their
//! tables, the machine (CPU model and cores from /proc/cpuinfo), the command
//! and the load average. The hand-written text around the markers is kept.
//! It then draws `docs/benchmarks/cost-vs-belt-speed.svg` from the page's
//! speeds table (`examples/cost_plot.py`, matplotlib from `.venv`), and
//! copies that table's first part (real-time factor against crank speed)
//! into the FMU's manual, `docs/fmu-manual.md`, between
//! `<!-- speeds:begin -->` and `<!-- speeds:end -->`, with the machine and
//! the command: the manual ships inside the FMU, where the benchmark page
//! cannot be linked.
//! No date or commit goes into the page (the docs describe the product as it
//! is; `xtask/src/hygiene.rs` refuses both): git records when the section
//! was regenerated.
//!
//! By default (about 9 minutes of one core, its build included) `benches/belt.rs` runs every
//! section but `accuracy` (`rhs default fmu scaling kubas speeds`) and the stiff
//! method's accuracy on the 5PK drive at relTol 1e-4 and 1e-5 only (`accuracy
//! --method 2 --drive 5pk --rtol 1e-4,1e-5`, against the RKF45 reference),
//! and `benches/stiff.rs` all sections but the hour-long `kubas`: the figures
//! the speed targets are stated in (right-hand side per body, the stiff
//! method's real-time factor).
//!
//! * `--full`: `benches/belt.rs` all sections, its accuracy section at every
//!   tolerance on both drives for both methods (over an hour on the shared
//!   development machine);
//! * `--quick`: short horizons (a smoke run of the whole chain; the figures
//!   are not the documented ones);
//! * `--core N`: pins this process, and so cargo and the benchmarks it
//!   starts, to core N (sched_setaffinity) - the figures are CPU times of
//!   one thread, so one quiet core is what they need;
//! * `--no-docs`: print only, leave docs/benchmarks.md alone.

use crate::{cargo, root, Result};
use std::fs;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Instant;

const BEGIN: &str = "<!-- bench:begin -->";
const END: &str = "<!-- bench:end -->";
/// Markers of the speeds table in the FMU's manual.
const MANUAL_BEGIN: &str = "<!-- speeds:begin -->";
const MANUAL_END: &str = "<!-- speeds:end -->";
/// The header of the speeds section's first table (`benches/speeds/mod.rs`).
const SPEEDS_HEADER: &str = "| drive | method | 800 rpm |";
/// The picture of the cost against belt speed, drawn from the speeds table.
const COST_PLOT: &str = "docs/benchmarks/cost-vs-belt-speed.svg";

struct Options {
    full: bool,
    quick: bool,
    core: Option<usize>,
    docs: bool,
}

fn parse(args: &[String]) -> Result<Options> {
    let mut o = Options {
        full: false,
        quick: false,
        core: None,
        docs: true,
    };
    let mut it = args.iter().filter(|a| a.as_str() != "--");
    while let Some(a) = it.next() {
        match a.as_str() {
            "--full" => o.full = true,
            "--quick" => o.quick = true,
            "--no-docs" => o.docs = false,
            "--core" => {
                let n = it
                    .next()
                    .and_then(|s| s.parse().ok())
                    .ok_or("--core needs a core number")?;
                o.core = Some(n);
            }
            other => {
                return Err(format!(
                    "bench: unknown argument {other} (usage: cargo xtask bench [--full] [--quick] [--core N] [--no-docs])"
                ))
            }
        }
    }
    Ok(o)
}

/// Pins the calling process (and the children it starts later) to `core`.
fn pin(core: usize) -> Result<()> {
    if core >= libc::CPU_SETSIZE as usize {
        return Err(format!("--core {core}: out of range"));
    }
    // SAFETY: cpu_set_t is plain data, zero-initialised and then filled by
    // the libc helpers; pid 0 is this process.
    let rc = unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_ZERO(&mut set);
        libc::CPU_SET(core, &mut set);
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set)
    };
    if rc != 0 {
        return Err(format!(
            "--core {core}: sched_setaffinity failed: {}",
            std::io::Error::last_os_error()
        ));
    }
    Ok(())
}

/// Runs `cmd`, echoing its standard output line by line (progress) and
/// returning it.
fn run_capture(cmd: &mut Command, what: &str) -> Result<String> {
    eprintln!("xtask: {what}: {cmd:?}");
    let t = Instant::now();
    let mut child = cmd
        .current_dir(root())
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    let mut out = String::new();
    let stdout = child.stdout.take().expect("piped");
    for line in BufReader::new(stdout).lines() {
        let line = line.map_err(|e| format!("{what}: reading its output: {e}"))?;
        println!("{line}");
        out.push_str(&line);
        out.push('\n');
    }
    let status = child.wait().map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("{what} failed ({status})"));
    }
    eprintln!("xtask: {what}: done in {:.0} s", t.elapsed().as_secs_f64());
    Ok(out)
}

/// CPU model and logical core count from /proc/cpuinfo.
fn machine() -> String {
    let info = fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |name: &str| {
        info.lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
    };
    let cores = info.lines().filter(|l| l.starts_with("processor")).count();
    let flags = field("flags").unwrap_or_default();
    let simd: Vec<&str> = ["avx2", "fma", "avx512f"]
        .into_iter()
        .filter(|f| flags.split_whitespace().any(|x| x == *f))
        .collect();
    format!(
        "`{}` ({} MHz), {cores} logical cores, SIMD: {}",
        field("model name").unwrap_or_else(|| "unknown CPU".into()),
        field("cpu MHz").unwrap_or_else(|| "?".into()),
        if simd.is_empty() {
            "baseline only".to_string()
        } else {
            simd.join(", ")
        }
    )
}

fn load_average() -> String {
    fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// The belt suite's output as markdown: its section headings one level
/// below the generated section's, blank lines around tables and after
/// headings, other lines as paragraphs.
fn as_markdown(out: &str) -> String {
    let mut md = String::new();
    let mut prev_table = false;
    for line in out.lines() {
        let table = line.starts_with('|');
        if table != prev_table || line.starts_with("## ") {
            md.push('\n');
        }
        match line.strip_prefix("## ") {
            Some(h) => md.push_str(&format!("#### {h}\n\n")),
            None if table || line.trim().is_empty() => md.push_str(&format!("{line}\n")),
            None => md.push_str(&format!("{line}\n\n")),
        }
        prev_table = table;
    }
    md
}

/// The sections of `benches/belt.rs` run (all with `--full`; without, all
/// but the hour-long `accuracy`).
fn belt_sections(full: bool) -> &'static [&'static str] {
    if full {
        &["all"]
    } else {
        &["rhs", "default", "fmu", "scaling", "kubas", "speeds"]
    }
}

/// The stiff method's accuracy run: every tolerance on both drives with
/// `--full`, else the 5PK drive at the default relTol 1e-4 and at 1e-5.
fn stiff_accuracy_args(full: bool) -> &'static [&'static str] {
    if full {
        &["accuracy", "--method", "2"]
    } else {
        &[
            "accuracy",
            "--method",
            "2",
            "--drive",
            "5pk",
            "--rtol",
            "1e-4,1e-5",
        ]
    }
}

/// Replaces the text between the markers in `doc` with `body`.
fn splice(doc: &str, body: &str) -> Result<String> {
    splice_between(doc, "docs/benchmarks.md", BEGIN, END, body)
}

/// Replaces the text between `begin` and `end` in `doc` (the file `what`)
/// with `body`.
fn splice_between(doc: &str, what: &str, begin: &str, end: &str, body: &str) -> Result<String> {
    let (Some(b), Some(e)) = (doc.find(begin), doc.find(end)) else {
        return Err(format!("{what} has no {begin} ... {end} markers"));
    };
    if e < b {
        return Err(format!("{what}: the end marker precedes the begin marker"));
    }
    Ok(format!("{}{begin}\n{body}{}", &doc[..b], &doc[e..]))
}

/// The speeds section's first table (real-time factor against crank speed)
/// from the belt suite's output, with the machine and the command, for the
/// FMU's manual; `None` when the run had no speeds section.
fn manual_speeds(belt_out: &str, machine: &str, cmd: &str) -> Option<String> {
    let mut lines = belt_out
        .lines()
        .skip_while(|l| !l.starts_with(SPEEDS_HEADER));
    let table: Vec<&str> = lines.by_ref().take_while(|l| l.starts_with('|')).collect();
    if table.is_empty() {
        return None;
    }
    Some(format!(
        "Real-time factor (simulated time over CPU time of one core; above 1 is faster than real time) at \
         relTol 10⁻⁴ and 1 ms communication steps, the load torques held at their idle values; measured by \
         `{cmd}` (section `cargo bench --bench belt -- speeds`) on {machine}:\n\n{}\n",
        table.join("\n")
    ))
}

pub fn bench(args: &[String]) -> Result<()> {
    let o = parse(args)?;
    if let Some(core) = o.core {
        pin(core)?;
        eprintln!("xtask: bench: pinned to core {core}");
    }
    let start_load = load_average();
    crate::run(
        cargo().args(["bench", "--bench", "belt", "--bench", "stiff", "--no-run"]),
        "build the benchmarks (release profile, baseline x86-64)",
    )?;
    let mut belt = cargo();
    belt.args(["bench", "--bench", "belt", "--"]);
    belt.args(belt_sections(o.full));
    if o.quick {
        belt.arg("--quick");
    }
    let mut belt_out = run_capture(
        &mut belt,
        &format!("benches/belt.rs {}", belt_sections(o.full).join(" ")),
    )?;
    // the stiff method's accuracy against the same RKF45 reference (#8)
    let mut stiff_accuracy = cargo();
    stiff_accuracy.args(["bench", "--bench", "belt", "--"]);
    stiff_accuracy.args(stiff_accuracy_args(o.full));
    if o.quick {
        stiff_accuracy.arg("--quick");
    }
    belt_out.push_str(&run_capture(
        &mut stiff_accuracy,
        &format!("benches/belt.rs {}", stiff_accuracy_args(o.full).join(" ")),
    )?);
    let mut stiff = cargo();
    stiff.args(["bench", "--bench", "stiff"]);
    if o.quick {
        stiff.env("BELT_BENCH_QUICK", "1");
    }
    let stiff_out = run_capture(
        &mut stiff,
        "benches/stiff.rs (all sections but kubas, which takes over an hour)",
    )?;

    let speeds_table = &belt_out;
    let belt_md = as_markdown(&belt_out);
    let mut cmd = String::from("cargo xtask bench");
    if o.full {
        cmd.push_str(" --full");
    }
    if o.quick {
        cmd.push_str(" --quick");
    }
    if let Some(c) = o.core {
        cmd.push_str(&format!(" --core {c}"));
    }
    let machine = machine();
    let body = format!(
        "## Latest run (generated by `cargo xtask bench`)\n\n\
         - command: `{cmd}`{quick}\n\
         - machine: {machine}\n\
         - pinned to: {pinned}; load average at start {start_load}, at end {end_load}\n\
         - times: CPU time of the benchmark thread (see above)\n\n\
         ### benches/belt.rs\n\n{belt_md}\n### benches/stiff.rs\n\n```text\n{stiff_out}```\n",
        quick = if o.quick {
            " (**quick smoke run: short horizons, not the documented figures**)"
        } else if o.full {
            ""
        } else {
            " (the default subset: every section of `benches/belt.rs` but `accuracy`, which runs for the \
             stiff method on the 5PK drive at relTol 1e-4 and 1e-5 only; `--full` runs all)"
        },
        machine = machine,
        pinned = o
            .core
            .map(|c| format!("core {c}"))
            .unwrap_or_else(|| "not pinned".into()),
        end_load = load_average(),
    );
    if o.docs {
        let path = root().join("docs/benchmarks.md");
        let doc = fs::read_to_string(&path).map_err(|e| format!("reading {path:?}: {e}"))?;
        fs::write(&path, splice(&doc, &body)?).map_err(|e| format!("writing {path:?}: {e}"))?;
        eprintln!("xtask: bench: docs/benchmarks.md updated between the markers");
        if let Some(table) = manual_speeds(speeds_table, &machine, &cmd) {
            let path = root().join("docs/fmu-manual.md");
            let doc = fs::read_to_string(&path).map_err(|e| format!("reading {path:?}: {e}"))?;
            let doc = splice_between(&doc, "docs/fmu-manual.md", MANUAL_BEGIN, MANUAL_END, &table)?;
            fs::write(&path, doc).map_err(|e| format!("writing {path:?}: {e}"))?;
            eprintln!("xtask: bench: docs/fmu-manual.md's speeds table updated");
        }
        // the cost against belt speed, drawn from the page's speeds table
        crate::venv()?;
        crate::run(
            Command::new(crate::venv_python())
                .current_dir(root())
                .args(["examples/cost_plot.py", "docs/benchmarks.md", COST_PLOT]),
            "the cost against belt speed (examples/cost_plot.py)",
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splice_keeps_the_text_around_the_markers() {
        let doc = format!("intro\n{BEGIN}\nold table\n{END}\noutro\n");
        let new = splice(&doc, "new table\n").unwrap();
        assert_eq!(new, format!("intro\n{BEGIN}\nnew table\n{END}\noutro\n"));
        assert!(splice("no markers", "x").is_err());
        assert!(splice(&format!("{END} {BEGIN}"), "x").is_err());
    }

    #[test]
    fn the_manual_gets_the_speeds_table_only() {
        let out = "## Real-time factor\nnote\n| drive | method | 800 rpm | 2 000 rpm |\n|---|---|---|---|\n\
                   | acc4 | stiff | 1.1 | 0.7 |\n\n| drive | crank speed [rpm] |\n|---|---|\n";
        let t = manual_speeds(out, "CPU X", "cargo xtask bench").unwrap();
        assert!(t.contains("| acc4 | stiff | 1.1 | 0.7 |") && t.contains("CPU X"));
        assert!(!t.contains("crank speed [rpm]"), "{t}");
        assert!(manual_speeds("## RHS\n| a |\n", "m", "c").is_none());
        let doc = format!("a\n{MANUAL_BEGIN}\nold\n{MANUAL_END}\nb\n");
        let new = splice_between(&doc, "manual", MANUAL_BEGIN, MANUAL_END, &t).unwrap();
        assert!(new.starts_with("a\n") && new.ends_with(&format!("{MANUAL_END}\nb\n")));
        assert!(!new.contains("old"));
    }

    #[test]
    fn markdown_of_the_suite_output() {
        let md = as_markdown("## RHS\nnote\n| a |\n|---|\n| 1 |\nafter\n");
        assert_eq!(
            md,
            "\n#### RHS\n\nnote\n\n\n| a |\n|---|\n| 1 |\n\nafter\n\n"
        );
    }

    #[test]
    fn options() {
        let a = |v: &[&str]| parse(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        let o = a(&["--", "--quick", "--core", "0"]).unwrap();
        assert!(o.quick && o.core == Some(0) && o.docs && !o.full);
        assert!(a(&["--full"]).unwrap().full);
        assert!(a(&["--core"]).is_err());
        assert!(a(&["--bogus"]).is_err());
        assert!(!a(&["--no-docs"]).unwrap().docs);
    }
}
