//! Parsers for list-valued CLI arguments.

/// A parsed list of numbers (see [`number_list`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NumberList(pub Vec<f64>);

/// clap value parser for [`NumberList`].
pub fn number_list_arg(s: &str) -> Result<NumberList, String> {
    number_list(s).map(NumberList)
}

/// Parses a comma-separated list of numbers, e.g. `0,100,300`. Ranges `a:b:step` (inclusive of
/// `b` when it falls on the grid) may appear as items, e.g. `0:1000:50,1500`.
pub fn number_list(s: &str) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    for item in s.split(',').map(str::trim) {
        if item.is_empty() {
            return Err(format!("empty item in list '{s}'"));
        }
        if item.contains(':') {
            out.extend(range(item)?);
        } else {
            out.push(number(item)?);
        }
    }
    Ok(out)
}

/// Largest number of values one range may expand to.
const MAX_RANGE_VALUES: usize = 1_000_000;

/// Parses `start:end:step` into the inclusive grid start, start+step, …, ≤ end.
pub fn range(s: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let [a, b, step] = parts[..] else {
        return Err(format!("range '{s}' must be start:end:step"));
    };
    let (a, b, step) = (number(a)?, number(b)?, number(step)?);
    if step <= 0.0 || b < a {
        return Err(format!("range '{s}' needs start <= end and step > 0"));
    }
    let n = ((b - a) / step + 1e-9).floor() as usize + 1;
    if n > MAX_RANGE_VALUES {
        return Err(format!(
            "range '{s}' has {n} values, more than the {MAX_RANGE_VALUES} allowed"
        ));
    }
    Ok((0..n).map(|i| a + i as f64 * step).collect())
}

fn number(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !v.is_finite() {
        return Err(format!("'{s}' is not a finite number"));
    }
    Ok(v)
}

/// clap value parser for an `f32` flag: a finite number within the `f32` range (refuses `nan`,
/// `inf` and values like `1e39` that would become infinite), so a bad value is refused where it
/// enters, with the flag's name (clap adds it).
pub fn finite_f32(s: &str) -> Result<f32, String> {
    let v = number(s)?;
    if v.abs() > f32::MAX as f64 {
        return Err(format!("'{s}' is outside the range of a 32-bit float"));
    }
    Ok(v as f32)
}

/// clap value parser for an `f64` flag: a finite number (refuses `nan` and `inf`).
pub fn finite_f64(s: &str) -> Result<f64, String> {
    number(s)
}

/// clap value parser for a whole number in `lo..=hi` (the flag's sane range), e.g.
/// `value_parser = parse::int_in::<u32>(1, 65536)`.
pub fn int_in<T>(lo: T, hi: T) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy + Send + Sync + 'static,
{
    move |s: &str| {
        let v: T = s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a whole number in {lo}..={hi}"))?;
        if v < lo || v > hi {
            return Err(format!("{v} is outside {lo}..={hi}"));
        }
        Ok(v)
    }
}

/// Parses an image size `WIDTHxHEIGHT`, e.g. `1280x720`.
pub fn size(s: &str) -> Result<(usize, usize), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size '{s}' must be WIDTHxHEIGHT, e.g. 1280x720"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<usize>()
            .map_err(|_| format!("size '{s}' must be WIDTHxHEIGHT with whole numbers"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
        return Err(format!(
            "size '{s}' must be between 1x1 and {MAX_SIDE}x{MAX_SIDE}"
        ));
    }
    Ok((w, h))
}

/// Largest image side in pixels.
const MAX_SIDE: usize = 32_768;

/// Parses a 3-vector `x,y,z`.
pub fn vec3(s: &str) -> Result<[f32; 3], String> {
    let v = number_list(s)?;
    match v[..] {
        [x, y, z] => Ok([x as f32, y as f32, z as f32]),
        _ => Err(format!("'{s}' must be three numbers x,y,z")),
    }
}

/// Parses "MIN,MAX" (two finite numbers, MIN < MAX).
pub fn min_max(s: &str) -> Result<[f32; 2], String> {
    let v = number_list(s)?;
    match v[..] {
        [a, b] if a < b && (a as f32).is_finite() && (b as f32).is_finite() => {
            Ok([a as f32, b as f32])
        }
        _ => Err(format!("'{s}' must be two numbers MIN,MAX with MIN < MAX")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_ranges() {
        assert_eq!(number_list("0,100,300").unwrap(), vec![0.0, 100.0, 300.0]);
        assert_eq!(
            number_list("380:400:10").unwrap(),
            vec![380.0, 390.0, 400.0]
        );
        assert_eq!(number_list("1:2:0.5,7").unwrap(), vec![1.0, 1.5, 2.0, 7.0]);
        for bad in [
            "",
            "1,,2",
            "a",
            "1:2",
            "2:1:1",
            "1:2:0",
            "nan",
            "0:1e12:1e-3",
        ] {
            assert!(number_list(bad).is_err(), "{bad}");
        }
    }
}

/// A parsed list of frame numbers (`--frames`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameList(pub Vec<u64>);

/// clap value parser for [`FrameList`]: `A..B` (B excluded), `A..=B` or `A`.
pub fn frame_list(s: &str) -> std::result::Result<FrameList, String> {
    crate::pipeline::sequence::frames(s).map(FrameList)
}

/// clap value parser for a shard `K/N` (0 <= K < N).
pub fn shard(s: &str) -> std::result::Result<(u64, u64), String> {
    crate::pipeline::sequence::shard(s)
}

/// clap value parser for a flag whose value names a variant of `T` (a primitive, a preset, a
/// tone curve...): checked here, so a bad value is reported against the flag rather than the
/// scene-file key it overrides; kept as the string the scene description takes.
pub fn named<T>(s: &str) -> Result<String, String>
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    s.parse::<T>()
        .map(|_| s.to_string())
        .map_err(|e| e.to_string())
}
