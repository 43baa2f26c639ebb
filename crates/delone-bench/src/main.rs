//! delone-bench: side-by-side timings and peak memory of delone against
//! Triangle and TetGen (through `tritet`), spade and delaunator.
//!
//! Every (case, program) pair runs in its own child process (this binary
//! re-invoked with the hidden `--child CASE PROGRAM` argument) so that the
//! peak RSS of one program cannot leak into another's figure, and so that a
//! crashing reference only loses its own row. See README.md for the columns.
#![forbid(unsafe_code)]

mod cases;
mod chart;
mod child;
#[allow(dead_code)] // the reference executables, for cases and tests
mod refbin;
mod report;
mod result;

use std::io::{Read, Write};
use std::process::{Command, ExitCode, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use cases::{Case, DEFAULT_CASES, QUICK_CASES};
use child::{handles, PROGRAMS, SMALL};
use result::{Outcome, RunResult};

const USAGE: &str = "\
usage: delone-bench [options]

options:
  --quick            only the ~1e5-point cases (fast smoke run)
  --cases LIST       comma-separated case names, e.g. 2d-uniform-1e6,3d-grid-1e6
                     (form {2d,3d}-{uniform,grid,circle,sphere}-SIZE; circle is 2D,
                     sphere 3D; `all` = the default suite, `quick` = the quick suite;
                     meshing cases on ../shared/data, not in any suite:
                     2d-poly-NAME-qANGLEaAREA (2d/NAME.poly refined, delone vs triangle),
                     2d-poly-NAME-p (constrained triangulation only),
                     2d-segs-SIZE / 2d-holes-SIZE (generated PSLGs, plain CDT),
                     3d-surf-MODEL (surf/off/MODEL.off boundary recovery, delone vs tetgen-p),
                     3d-surfY-MODEL (the same preserving the surface, -Y: delone vs tetgen-pY),
                     3d-surfq-MODEL-qB (recovery + refinement to radius-edge B + optimisation),
                     3d-plc-NAME / 3d-plcq-NAME-qB (3d_plc/NAME.poly or .smesh, recovery /
                     refinement: delone vs tetgen-p / tetgen-pq; 3d-plc-@all and
                     3d-plcq-@all-qB run every PLC of 3d_plc);
                     model sets: 3d-surf-@SET and 3d-surfq-@SET-qB run every model of
                     shared/data/sets/SET.txt, `@SET<N` / `@SET>N` only those with fewer /
                     more than N triangles, e.g. 3d-surfq-@closed_clean<30000-q1.414)
  --programs LIST    comma-separated subset of: delone,triangle,spade,delaunator,
                     triangle-p (Triangle's executable, -p/-pq cases); TetGen 1.6's
                     executable: tetgen (3D point sets), tetgen-p (-p), tetgen-pY (-pY),
                     tetgen-pq (-pqB), tetgen-pq-keep (-p180qB: every input triangle
                     kept as a facet, as delone does; only when named); TetGen 1.5 as
                     bundled in tritet, only when named: tetgen15 (its library: point
                     sets, 3d-surf as -pq), tetgen15-p, tetgen15-pY, tetgen15-pq,
                     tetgen15-pq-keep (its executable)
  --repeat N         timed runs per small case (<= 200000 points), median reported;
                     larger cases always run once (default 3)
  --timeout SECS     kill a child after this many seconds (default 600)
  --markdown         print the table as Markdown
  --list             list the default and quick cases and the programs
  --dihedral-chart MODEL RATIO OUT.svg
                     mesh surf/off/MODEL.off with delone and TetGen at -pqRATIO and
                     draw both dihedral-angle distributions as an SVG bar chart
  -h, --help         this text
";

#[derive(Debug)]
struct Options {
    cases: Vec<Case>,
    programs: Vec<String>,
    repeat: usize,
    timeout: Duration,
    markdown: bool,
}

enum Mode {
    Bench(Options),
    Child {
        case: Case,
        program: String,
        repeat: usize,
    },
    Help,
    List,
    Chart {
        model: String,
        ratio: String,
        out: String,
    },
}

fn program_names() -> Vec<&'static str> {
    let mut names: Vec<&str> = Vec::new();
    for &(p, _) in PROGRAMS {
        if !names.contains(&p) {
            names.push(p);
        }
    }
    names
}

fn parse_cases(list: &str) -> Result<Vec<Case>, String> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let group = match name {
            "all" | "default" => Some(DEFAULT_CASES),
            "quick" => Some(QUICK_CASES),
            _ => None,
        };
        match group {
            Some(g) => {
                for n in g {
                    out.push(Case::parse(n).map_err(|e| e.to_string())?);
                }
            }
            None if name.contains("-@") => {
                for n in expand_set(name)? {
                    out.push(Case::parse(&n).map_err(|e| e.to_string())?);
                }
            }
            None => out.push(Case::parse(name).map_err(|e| e.to_string())?),
        }
    }
    if out.is_empty() {
        return Err("--cases: empty list".into());
    }
    Ok(out)
}

/// Expands `3d-surf-@SET[<N|>N]` and `3d-surfq-@SET[<N|>N]-qB` into one
/// case per surface model listed in `shared/data/sets/SET.txt` (lines
/// `surf/off/NAME.off<TAB>triangles`), optionally only the models with
/// fewer (`<N`) or more (`>N`) input triangles than N.
fn expand_set(name: &str) -> Result<Vec<String>, String> {
    let (prefix, rest) = name.split_once("-@").unwrap_or((name, ""));
    if prefix == "3d-plc" || prefix == "3d-plcq" {
        return expand_plcs(name, prefix, rest);
    }
    if prefix != "3d-surf" && prefix != "3d-surfq" && prefix != "3d-surfY" {
        return Err(format!(
            "`{name}`: model sets are for 3d-surf, 3d-surfY and 3d-surfq cases"
        ));
    }
    let (set, suffix) = match rest.rsplit_once("-q") {
        Some((s, b)) if prefix == "3d-surfq" => (s, format!("-q{b}")),
        _ if prefix == "3d-surfq" => return Err(format!("`{name}`: missing -qB")),
        _ => (rest, String::new()),
    };
    let (set, keep): (&str, Box<dyn Fn(usize) -> bool>) = if let Some((s, n)) = set.split_once('<')
    {
        let n: usize = n.parse().map_err(|_| format!("`{name}`: bad bound"))?;
        (s, Box::new(move |t| t < n))
    } else if let Some((s, n)) = set.split_once('>') {
        let n: usize = n.parse().map_err(|_| format!("`{name}`: bad bound"))?;
        (s, Box::new(move |t| t > n))
    } else {
        (set, Box::new(|_| true))
    };
    let dir = cases::data_dir().ok_or("shared/data not found")?;
    let path = dir.join("sets").join(format!("{set}.txt"));
    let text =
        std::fs::read_to_string(&path).map_err(|e| format!("`{name}`: {}: {e}", path.display()))?;
    let mut out = Vec::new();
    for line in text.lines() {
        let mut f = line.split_whitespace();
        let (Some(file), Some(count)) = (f.next(), f.next()) else {
            continue;
        };
        let Some(model) = file
            .strip_prefix("surf/off/")
            .and_then(|m| m.strip_suffix(".off"))
        else {
            continue;
        };
        if count.parse().is_ok_and(|t: usize| keep(t)) {
            out.push(format!("{prefix}-{model}{suffix}"));
        }
    }
    if out.is_empty() {
        return Err(format!("`{name}`: no model in {}", path.display()));
    }
    Ok(out)
}

/// Expands `3d-plc-@all` and `3d-plcq-@all-qB` into one case per `.poly`
/// or `.smesh` file of `shared/data/3d_plc`, in name order.
fn expand_plcs(name: &str, prefix: &str, rest: &str) -> Result<Vec<String>, String> {
    let suffix = match (prefix, rest.strip_prefix("all")) {
        ("3d-plc", Some("")) => String::new(),
        ("3d-plcq", Some(b)) if b.starts_with("-q") => b.to_string(),
        _ => return Err(format!("`{name}`: expected 3d-plc-@all or 3d-plcq-@all-qB")),
    };
    let mut names = cases::data_names("3d_plc", "poly");
    names.extend(cases::data_names("3d_plc", "smesh"));
    names.sort();
    names.dedup();
    if names.is_empty() {
        return Err(format!(
            "`{name}`: no .poly or .smesh file in shared/data/3d_plc"
        ));
    }
    Ok(names
        .into_iter()
        .map(|n| format!("{prefix}-{n}{suffix}"))
        .collect())
}

fn parse_args(args: &[String]) -> Result<Mode, String> {
    let mut quick = false;
    let mut cases: Option<Vec<Case>> = None;
    let mut programs: Option<Vec<String>> = None;
    let mut repeat = 3usize;
    let mut timeout = 600u64;
    let mut markdown = false;
    let mut child: Option<(String, String)> = None;
    let mut i = 0;
    let value = |i: &mut usize, flag: &str| -> Result<String, String> {
        *i += 1;
        args.get(*i)
            .cloned()
            .ok_or_else(|| format!("{flag} needs a value"))
    };
    while i < args.len() {
        match args[i].as_str() {
            "-h" | "--help" => return Ok(Mode::Help),
            "--list" => return Ok(Mode::List),
            "--dihedral-chart" => {
                let model = value(&mut i, "--dihedral-chart")?;
                let ratio = value(&mut i, "--dihedral-chart")?;
                let out = value(&mut i, "--dihedral-chart")?;
                return Ok(Mode::Chart { model, ratio, out });
            }
            "--quick" => quick = true,
            "--markdown" => markdown = true,
            "--cases" => cases = Some(parse_cases(&value(&mut i, "--cases")?)?),
            "--programs" => {
                let v = value(&mut i, "--programs")?;
                let known = program_names();
                let mut ps = Vec::new();
                for p in v.split(',').map(str::trim).filter(|s| !s.is_empty()) {
                    if !known.contains(&p) {
                        return Err(format!(
                            "unknown program `{p}` (known: {})",
                            known.join(", ")
                        ));
                    }
                    ps.push(p.to_string());
                }
                if ps.is_empty() {
                    return Err("--programs: empty list".into());
                }
                programs = Some(ps);
            }
            "--repeat" => {
                let v = value(&mut i, "--repeat")?;
                repeat = v
                    .parse()
                    .ok()
                    .filter(|&r| r >= 1)
                    .ok_or_else(|| format!("--repeat: `{v}` is not a positive integer"))?;
            }
            "--timeout" => {
                let v = value(&mut i, "--timeout")?;
                timeout = v
                    .parse()
                    .ok()
                    .filter(|&t| t >= 1)
                    .ok_or_else(|| format!("--timeout: `{v}` is not a positive integer"))?;
            }
            "--child" => {
                let c = value(&mut i, "--child")?;
                let p = value(&mut i, "--child")?;
                child = Some((c, p));
            }
            a => return Err(format!("unknown argument `{a}`")),
        }
        i += 1;
    }
    if let Some((c, p)) = child {
        let case = Case::parse(&c).map_err(|e| e.to_string())?;
        return Ok(Mode::Child {
            case,
            program: p,
            repeat,
        });
    }
    let cases = match cases {
        Some(c) => c,
        None => {
            let names = if quick { QUICK_CASES } else { DEFAULT_CASES };
            names
                .iter()
                .map(|n| Case::parse(n).map_err(|e| e.to_string()))
                .collect::<Result<_, _>>()?
        }
    };
    // The default set leaves out the secondary programs (TetGen 1.5, and
    // TetGen without its facet merging): they are asked for by name.
    let programs = programs.unwrap_or_else(|| {
        program_names()
            .into_iter()
            .filter(|&p| !child::only_when_named(p))
            .map(str::to_string)
            .collect()
    });
    Ok(Mode::Bench(Options {
        cases,
        programs,
        repeat,
        timeout: Duration::from_secs(timeout),
        markdown,
    }))
}

fn describe_status(st: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = st.signal() {
            let name = match sig {
                6 => " (SIGABRT)",
                9 => " (SIGKILL, out of memory?)",
                11 => " (SIGSEGV)",
                _ => "",
            };
            return format!("killed by signal {sig}{name}");
        }
    }
    match st.code() {
        Some(c) => format!("exit code {c}"),
        None => "abnormal exit".into(),
    }
}

fn last_line(s: &str) -> Option<String> {
    let l = s.lines().rev().map(str::trim).find(|l| !l.is_empty())?;
    let mut l: String = l.chars().take(160).collect();
    if l.len() < s.trim().len() && l.chars().count() == 160 {
        l.push('…');
    }
    Some(l)
}

/// Runs one (case, program) pair in a child process.
fn spawn_child(case: &Case, program: &str, opts: &Options) -> RunResult {
    let n = case.n();
    let fail = |why: String| RunResult::failed(&case.name, program, n, why);
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => return fail(format!("cannot locate own executable: {e}")),
    };
    let mut child = match Command::new(exe)
        .args(["--child", &case.name, program, "--repeat"])
        .arg(opts.repeat.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return fail(format!("cannot start child: {e}")),
    };
    // Drain both pipes on threads so a chatty child never blocks.
    let drain = |p: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            if let Some(mut p) = p {
                let _ = p.read_to_end(&mut buf);
            }
            String::from_utf8_lossy(&buf).into_owned()
        })
    };
    let out = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let err = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(st)) => break Ok(st),
            Ok(None) if start.elapsed() > opts.timeout => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!("timeout after {} s", opts.timeout.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => break Err(format!("cannot wait for child: {e}")),
        }
    };
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    let status = match status {
        Ok(st) => st,
        Err(why) => return fail(why),
    };
    match RunResult::from_output(&stdout) {
        Some(Ok(r)) if status.success() => r,
        Some(Err(e)) => fail(format!("unreadable result line: {e}")),
        _ => {
            let mut why = describe_status(status);
            if let Some(l) = last_line(&stderr) {
                why.push_str(": ");
                why.push_str(&l);
            }
            fail(why)
        }
    }
}

fn cpu_model() -> Option<String> {
    let s = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    s.lines()
        .find_map(|l| l.strip_prefix("model name")?.split_once(':'))
        .map(|(_, m)| m.trim().to_string())
}

fn bench(opts: &Options) {
    let jobs: Vec<(&Case, &str)> = opts
        .cases
        .iter()
        .flat_map(|c| {
            opts.programs
                .iter()
                .filter(move |p| handles(p, c))
                .map(move |p| (c, p.as_str()))
        })
        .collect();
    let mut results = Vec::with_capacity(jobs.len());
    for (k, (case, program)) in jobs.iter().enumerate() {
        eprint!(
            "[{}/{}] {} ({}, n = {}) {} ... ",
            k + 1,
            jobs.len(),
            case.name,
            case.describe(),
            case.n(),
            program
        );
        let _ = std::io::stderr().flush();
        let r = spawn_child(case, program, opts);
        match &r.outcome {
            Outcome::Ok => eprintln!("{:.4} s, {} elements", r.seconds, r.elements),
            Outcome::Error(m) => eprintln!("error: {m}"),
            Outcome::Invalid(m) => {
                eprintln!("{:.4} s, {} elements, INVALID: {m}", r.seconds, r.elements)
            }
            Outcome::Failed(m) => eprintln!("failed: {m}"),
        }
        results.push(r);
    }

    let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
    let header = format!(
        "delone-bench {} — cpu: {} ({cpus} threads available); small cases (<= {SMALL} points): \
         1 warm-up + median of {} runs; larger: 1 run",
        env!("CARGO_PKG_VERSION"),
        cpu_model().unwrap_or_else(|| "unknown".into()),
        opts.repeat
    );
    if opts.markdown {
        println!("{header}\n");
        print!("{}", report::markdown(&results));
        println!("\n{}", report::determinism(&results));
        println!("{}", report::validity(&results));
    } else {
        println!("{header}\n");
        print!("{}", report::plain(&results));
        println!("\n{}", report::determinism(&results));
        println!("{}", report::validity(&results));
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse_args(&args) {
        Err(e) => {
            eprintln!("delone-bench: {e}\n\n{USAGE}");
            ExitCode::from(2)
        }
        Ok(Mode::Help) => {
            print!("{USAGE}");
            ExitCode::SUCCESS
        }
        Ok(Mode::Chart { model, ratio, out }) => match chart::run(&model, &ratio, &out) {
            Ok(summary) => {
                println!("{summary}\nwrote {out}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("delone-bench: {e}");
                ExitCode::FAILURE
            }
        },
        Ok(Mode::List) => {
            println!("default cases: {}", DEFAULT_CASES.join(", "));
            println!("quick cases:   {}", QUICK_CASES.join(", "));
            println!("programs:      {}", program_names().join(", "));
            println!(
                "file cases (need the shared data directory{}):",
                cases::data_dir().map_or(", not found".into(), |d| format!(" {}", d.display()))
            );
            println!("  2d-poly-NAME-qANGLEaAREA, 2d-poly-NAME-p (delone, triangle); NAME one of:");
            println!("    {}", cases::data_names("2d", "poly").join(", "));
            println!("  3d-surf-MODEL (delone, tetgen-p); MODEL one of:");
            println!("    {}", cases::data_names("surf/off", "off").join(", "));
            ExitCode::SUCCESS
        }
        Ok(Mode::Child {
            case,
            program,
            repeat,
        }) => {
            // Fault injection for the harness's own tests: abort this child
            // as a crashing reference would.
            if std::env::var("DELONE_BENCH_ABORT_PROGRAM").is_ok_and(|p| p == program) {
                eprintln!(
                    "delone-bench: aborting `{program}` as requested by DELONE_BENCH_ABORT_PROGRAM"
                );
                std::process::abort();
            }
            let r = child::run_child(&case, &program, repeat);
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out);
            let _ = writeln!(out, "{}", r.to_line());
            let _ = out.flush();
            ExitCode::SUCCESS
        }
        Ok(Mode::Bench(opts)) => {
            bench(&opts);
            ExitCode::SUCCESS
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn defaults_and_quick() {
        let Ok(Mode::Bench(o)) = parse_args(&[]) else {
            panic!()
        };
        assert_eq!(o.cases.len(), DEFAULT_CASES.len());
        assert_eq!(o.programs.len(), 9);
        assert!(!o.programs.iter().any(|p| p == "tetgen-pq-keep"));
        assert!(!o.programs.iter().any(|p| p.starts_with("tetgen15")));
        assert!(o.programs.iter().any(|p| p == "tetgen-pq"));
        assert_eq!(o.repeat, 3);
        let Ok(Mode::Bench(o)) = parse_args(&args("--programs delone,tetgen-pq-keep")) else {
            panic!()
        };
        assert_eq!(o.programs, ["delone", "tetgen-pq-keep"]);
        let Ok(Mode::Bench(o)) = parse_args(&args("--quick --repeat 7 --markdown")) else {
            panic!()
        };
        assert!(o.cases.iter().all(|c| c.n() <= SMALL));
        assert_eq!(o.repeat, 7);
        assert!(o.markdown);
    }

    #[test]
    fn lists_and_errors() {
        let Ok(Mode::Bench(o)) = parse_args(&args(
            "--cases 2d-uniform-1e3,quick --programs triangle,tetgen",
        )) else {
            panic!()
        };
        assert_eq!(o.cases.len(), 1 + QUICK_CASES.len());
        assert_eq!(o.programs, ["triangle", "tetgen"]);
        for bad in [
            "--cases 2d-cube-1e3",
            "--programs cgal",
            "--repeat 0",
            "--repeat",
            "--bogus",
            "--child 2d-uniform-1e3",
        ] {
            assert!(parse_args(&args(bad)).is_err(), "{bad}");
        }
        let Ok(Mode::Bench(o)) = parse_args(&args(
            "--cases 2d-poly-la-q30a0.001,2d-poly-la-p,3d-surf-c3d_spot",
        )) else {
            panic!()
        };
        assert_eq!(o.cases.len(), 3);
        assert!(parse_args(&args("--cases 2d-poly-la-q30a")).is_err());
        assert!(matches!(
            parse_args(&args("--child 2d-poly-la-q30a0.001 triangle")),
            Ok(Mode::Child { .. })
        ));
        assert!(matches!(
            parse_args(&args("--child 3d-grid-27 tetgen --repeat 2")),
            Ok(Mode::Child { repeat: 2, .. })
        ));
    }

    #[test]
    fn last_line_of_stderr() {
        assert_eq!(
            last_line("a\nthread panicked\n\n"),
            Some("thread panicked".into())
        );
        assert_eq!(last_line("  \n"), None);
    }
}
