//! One (case, program) measurement and its one-line wire format between
//! the child process and the parent.

/// Prefix of the machine-readable line a child prints on stdout.
pub const TAG: &str = "DELONE-BENCH-RESULT";

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The program produced a triangulation.
    Ok,
    /// The program returned an error (message).
    Error(String),
    /// The program produced a result that delone's validator rejects
    /// (the violation); its figures are shown but no ratios.
    Invalid(String),
    /// The child crashed, timed out or printed no result (reason).
    Failed(String),
}

/// One measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct RunResult {
    /// Case name.
    pub case: String,
    /// Program name.
    pub program: String,
    /// Number of input points.
    pub n: usize,
    /// Median wall time of the timed runs, seconds (NaN if none).
    pub seconds: f64,
    /// Number of timed runs.
    pub runs: usize,
    /// Peak RSS of the whole child (VmHWM), kB.
    pub peak_kb: Option<u64>,
    /// RSS after generating the points, before anything else, kB.
    pub base_kb: Option<u64>,
    /// Largest rise of RSS during the timed call alone (peak counter reset
    /// just before the call), kB; `None` where the counter cannot be reset.
    pub call_kb: Option<u64>,
    /// Triangles / tetrahedra produced.
    pub elements: usize,
    /// Whether repeated runs gave bit-identical output (delone only).
    pub deterministic: Option<bool>,
    /// Whether delone's validator accepted the output (delone only).
    pub valid: Option<bool>,
    /// Extra figures of the file cases, `key=value` pairs joined by `,`
    /// without spaces (e.g. `steiner=12,min_angle=30.1`); empty if none.
    pub info: String,
    /// How it ended.
    pub outcome: Outcome,
}

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map_or_else(|| "-".to_string(), |x| x.to_string())
}

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn parse_yes_no(s: &str) -> Result<Option<bool>, String> {
    match s {
        "yes" => Ok(Some(true)),
        "no" => Ok(Some(false)),
        "-" => Ok(None),
        _ => Err(format!("bad yes/no value `{s}`")),
    }
}

fn parse_opt<T: std::str::FromStr>(s: &str) -> Result<Option<T>, String> {
    if s == "-" {
        Ok(None)
    } else {
        s.parse().map(Some).map_err(|_| format!("bad value `{s}`"))
    }
}

impl RunResult {
    /// A result for a child that produced no result line.
    pub fn failed(case: &str, program: &str, n: usize, reason: String) -> Self {
        RunResult {
            case: case.to_string(),
            program: program.to_string(),
            n,
            seconds: f64::NAN,
            runs: 0,
            peak_kb: None,
            base_kb: None,
            call_kb: None,
            elements: 0,
            deterministic: None,
            valid: None,
            info: String::new(),
            outcome: Outcome::Failed(reason),
        }
    }

    /// Peak minus baseline, in bytes per input point.
    pub fn bytes_per_point(&self) -> Option<f64> {
        let (p, b) = (self.peak_kb?, self.base_kb?);
        (self.n > 0).then(|| p.saturating_sub(b) as f64 * 1024.0 / self.n as f64)
    }

    /// The timed call's own RSS rise, in bytes per input point.
    pub fn call_bytes_per_point(&self) -> Option<f64> {
        let c = self.call_kb?;
        (self.n > 0).then(|| c as f64 * 1024.0 / self.n as f64)
    }

    /// Serialises to one line: `TAG key=value ... outcome=KIND message`.
    /// Every field but the message is free of spaces; the message comes
    /// last and runs to the end of the line.
    pub fn to_line(&self) -> String {
        let (kind, msg) = match &self.outcome {
            Outcome::Ok => ("ok", String::new()),
            Outcome::Error(m) => ("error", m.replace(['\n', '\r'], " ")),
            Outcome::Invalid(m) => ("invalid", m.replace(['\n', '\r'], " ")),
            Outcome::Failed(m) => ("failed", m.replace(['\n', '\r'], " ")),
        };
        format!(
            "{TAG} case={} program={} n={} seconds={:e} runs={} peak_kb={} base_kb={} call_kb={} elements={} deterministic={} valid={} info={} outcome={kind} {msg}",
            self.case,
            self.program,
            self.n,
            self.seconds,
            self.runs,
            opt(self.peak_kb),
            opt(self.base_kb),
            opt(self.call_kb),
            self.elements,
            opt(self.deterministic.map(yes_no)),
            opt(self.valid.map(yes_no)),
            if self.info.is_empty() {
                "-".to_string()
            } else {
                self.info.replace(char::is_whitespace, "_")
            },
        )
        .trim_end()
        .to_string()
    }

    /// Finds and parses the result line in a child's stdout.
    pub fn from_output(stdout: &str) -> Option<Result<RunResult, String>> {
        stdout
            .lines()
            .rev()
            .find(|l| l.starts_with(TAG))
            .map(RunResult::from_line)
    }

    /// Parses a line written by [`RunResult::to_line`].
    pub fn from_line(line: &str) -> Result<RunResult, String> {
        let rest = line
            .strip_prefix(TAG)
            .ok_or_else(|| "missing tag".to_string())?
            .trim_start();
        let (fields, tail) = match rest.find("outcome=") {
            Some(i) => (&rest[..i], &rest[i + "outcome=".len()..]),
            None => return Err("missing outcome".to_string()),
        };
        let get = |key: &str| -> Result<String, String> {
            fields
                .split_whitespace()
                .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
                .map(str::to_string)
                .ok_or_else(|| format!("missing field `{key}`"))
        };
        let case = get("case")?;
        let program = get("program")?;
        let num = |s: String| s.parse::<usize>().map_err(|_| format!("bad number `{s}`"));
        let n = num(get("n")?)?;
        let seconds: f64 = {
            let s = get("seconds")?;
            s.parse().map_err(|_| format!("bad seconds `{s}`"))?
        };
        let runs = num(get("runs")?)?;
        let peak_kb = parse_opt(&get("peak_kb")?)?;
        let base_kb = parse_opt(&get("base_kb")?)?;
        let call_kb = parse_opt(&get("call_kb")?)?;
        let elements = num(get("elements")?)?;
        let deterministic = parse_yes_no(&get("deterministic")?)?;
        let valid = parse_yes_no(&get("valid")?)?;
        let info = match get("info").as_deref() {
            Ok("-") | Err(_) => String::new(),
            Ok(i) => i.to_string(),
        };
        let (kind, msg) = tail.split_once(' ').unwrap_or((tail, ""));
        let msg = msg.trim().to_string();
        let outcome = match kind {
            "ok" => Outcome::Ok,
            "error" => Outcome::Error(msg),
            "invalid" => Outcome::Invalid(msg),
            "failed" => Outcome::Failed(msg),
            k => return Err(format!("bad outcome `{k}`")),
        };
        Ok(RunResult {
            case,
            program,
            n,
            seconds,
            runs,
            peak_kb,
            base_kb,
            call_kb,
            elements,
            deterministic,
            valid,
            info,
            outcome,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> RunResult {
        RunResult {
            case: "2d-uniform-1e5".into(),
            program: "triangle".into(),
            n: 100_000,
            seconds: 0.0423,
            runs: 5,
            peak_kb: Some(40_000),
            base_kb: Some(4_000),
            call_kb: Some(30_000),
            elements: 199_980,
            deterministic: None,
            valid: None,
            info: String::new(),
            outcome: Outcome::Ok,
        }
    }

    #[test]
    fn round_trip() {
        let mut r = sample();
        assert_eq!(RunResult::from_line(&r.to_line()).unwrap(), r);
        r.deterministic = Some(false);
        r.valid = Some(true);
        r.call_kb = None;
        assert_eq!(RunResult::from_line(&r.to_line()).unwrap(), r);
        r.info = "steiner=12,min_angle=30.02".into();
        assert_eq!(RunResult::from_line(&r.to_line()).unwrap(), r);
        r.valid = Some(false);
        r.outcome = Outcome::Invalid("tet 3 is not Delaunay".into());
        r.outcome = Outcome::Error("point 7 has a NaN or infinite coordinate".into());
        assert_eq!(RunResult::from_line(&r.to_line()).unwrap(), r);
        r.outcome = Outcome::Failed("multi\nline outcome=ok".into());
        let back = RunResult::from_line(&r.to_line()).unwrap();
        assert_eq!(
            back.outcome,
            Outcome::Failed("multi line outcome=ok".into())
        );
    }

    #[test]
    fn found_among_noise() {
        let r = sample();
        let out = format!("Triangle chatter\n{}\nmore chatter\n", r.to_line());
        assert_eq!(RunResult::from_output(&out).unwrap().unwrap(), r);
        assert!(RunResult::from_output("nothing here").is_none());
        assert!(RunResult::from_line("DELONE-BENCH-RESULT case=x outcome=ok").is_err());
    }

    #[test]
    fn per_point_figures() {
        let r = sample();
        let b = r.bytes_per_point().unwrap();
        assert!((b - 36_000.0 * 1024.0 / 100_000.0).abs() < 1e-9);
        let c = r.call_bytes_per_point().unwrap();
        assert!((c - 30_000.0 * 1024.0 / 100_000.0).abs() < 1e-9);
    }
}
