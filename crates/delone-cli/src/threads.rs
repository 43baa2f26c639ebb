//! `--threads N`: threads for `delone tri`'s quality refinement and for
//! reading and writing the `.node`/`.ele` files of `delone tet`'s point sets.

use crate::fail::Usage;

/// Parses the value of `--threads`: a whole number from 1 to 64.
pub fn parse(v: &str) -> Result<usize, Usage> {
    match v.parse::<usize>() {
        Ok(n) if (1..=64).contains(&n) => Ok(n),
        _ => Err(Usage(format!(
            "--threads needs a number of threads from 1 to 64, not {v:?}"
        ))),
    }
}

/// The threads to use: `--threads N`, else the library's default.
pub fn effective(given: Option<usize>) -> usize {
    given.unwrap_or_else(delone::tri::refine::default_threads)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_a_thread_count() {
        assert_eq!(parse("2").unwrap(), 2);
        assert!(parse("0").is_err());
        assert!(parse("x").unwrap_err().0.contains("--threads needs"));
        assert_eq!(effective(Some(3)), 3);
        assert!(effective(None) >= 1);
    }
}
