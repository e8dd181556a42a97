//! Frame sequences for `filmsplat render`: path patterns (`frame_{:04}.ply`), frame ranges,
//! shards for render farms, resume, keep-going.

use crate::{Error, Result};

/// Expands the first `{}` or `{:0N}` in `pattern` with `frame` (zero-padded to N digits).
/// Returns `None` if the pattern has no placeholder.
pub fn expand(pattern: &str, frame: u64) -> Result<Option<String>> {
    let Some(open) = pattern.find('{') else {
        return Ok(None);
    };
    let close = pattern[open..]
        .find('}')
        .map(|c| open + c)
        .ok_or_else(|| Error::invalid(format!("'{pattern}': unclosed '{{' in frame pattern")))?;
    let spec = &pattern[open + 1..close];
    let width = match spec {
        "" => 0,
        s if s.starts_with(":0") && s.len() > 2 => s[2..]
            .parse::<usize>()
            .ok()
            .filter(|w| *w <= 20)
            .ok_or_else(|| {
                Error::invalid(format!(
                    "'{pattern}': frame pattern must be {{}} or {{:0N}}"
                ))
            })?,
        _ => {
            return Err(Error::invalid(format!(
                "'{pattern}': frame pattern must be {{}} or {{:0N}}"
            )));
        }
    };
    Ok(Some(format!(
        "{}{frame:0width$}{}",
        &pattern[..open],
        &pattern[close + 1..]
    )))
}

/// A parsed list of frame numbers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameList(pub Vec<u64>);

/// clap value parser for [`FrameList`].
pub fn frame_list(s: &str) -> std::result::Result<FrameList, String> {
    frames(s).map(FrameList)
}

/// Parses a frame range `A..B` (B excluded) or `A..=B`, or a single frame `A`.
pub fn frames(s: &str) -> std::result::Result<Vec<u64>, String> {
    let bad = || format!("frames '{s}' must be A..B, A..=B or A (whole numbers)");
    let num = |v: &str| v.trim().parse::<u64>().map_err(|_| bad());
    let (a, b) = if let Some((a, b)) = s.split_once("..=") {
        (num(a)?, num(b)?.checked_add(1).ok_or_else(bad)?)
    } else if let Some((a, b)) = s.split_once("..") {
        (num(a)?, num(b)?)
    } else {
        let a = num(s)?;
        (a, a.checked_add(1).ok_or_else(bad)?)
    };
    if b <= a {
        return Err(format!("frames '{s}' is empty"));
    }
    if b - a > 10_000_000 {
        return Err(format!("frames '{s}' has more than 10 000 000 frames"));
    }
    Ok((a..b).collect())
}

/// Parses a shard `K/N` (0 <= K < N).
pub fn shard(s: &str) -> std::result::Result<(u64, u64), String> {
    let bad = || format!("shard '{s}' must be K/N with 0 <= K < N");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u64>().map_err(|_| bad())?,
        n.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The frames this shard renders: every N-th of `frames`, starting at the K-th.
pub fn sharded(frames: &[u64], shard: Option<(u64, u64)>) -> Vec<u64> {
    match shard {
        None => frames.to_vec(),
        Some((k, n)) => frames
            .iter()
            .copied()
            .skip(k as usize)
            .step_by(n as usize)
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_ranges_and_shards() {
        assert_eq!(expand("f_{:04}.ply", 7).unwrap().unwrap(), "f_0007.ply");
        assert_eq!(expand("f_{}.ply", 12).unwrap().unwrap(), "f_12.ply");
        assert_eq!(expand("plain.ply", 1).unwrap(), None);
        assert!(expand("f_{:x}.ply", 1).is_err());
        assert!(expand("f_{.ply", 1).is_err());
        assert_eq!(frames("3..6").unwrap(), vec![3, 4, 5]);
        assert_eq!(frames("3..=5").unwrap(), vec![3, 4, 5]);
        assert_eq!(frames("9").unwrap(), vec![9]);
        for bad in ["5..5", "a..3", "", "1..x"] {
            assert!(frames(bad).is_err(), "{bad}");
        }
        assert_eq!(shard("1/3").unwrap(), (1, 3));
        assert!(shard("3/3").is_err() && shard("1/0").is_err() && shard("x").is_err());
        let all: Vec<u64> = (0..10).collect();
        let mut union: Vec<u64> = (0..3).flat_map(|k| sharded(&all, Some((k, 3)))).collect();
        union.sort();
        assert_eq!(union, all);
        assert_eq!(sharded(&all, Some((1, 3))), vec![1, 4, 7]);
    }
}
