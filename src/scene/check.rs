//! Checks of a scene file's values that serde cannot make: every float finite and within the
//! `f32` range (TOML accepts `nan`, `inf` and `1e39`, which serde would turn into NaN or
//! infinity), and the line of a key, so every error can name the file and the line.

/// The first float in `table` that is not finite or lies outside the `f32` range, as its key
/// path (`camera.fov`, `light.2.radius`, `camera.position.1`) and value.
pub(super) fn bad_float(table: &toml::Table) -> Option<(Vec<String>, f64)> {
    fn walk(v: &toml::Value, path: &mut Vec<String>) -> Option<(Vec<String>, f64)> {
        match v {
            toml::Value::Float(f) if !(f.is_finite() && f.abs() <= f32::MAX as f64) => {
                Some((path.clone(), *f))
            }
            toml::Value::Table(t) => t.iter().find_map(|(k, v)| {
                path.push(k.clone());
                let r = walk(v, path);
                path.pop();
                r
            }),
            toml::Value::Array(a) => a.iter().enumerate().find_map(|(i, v)| {
                path.push(i.to_string());
                let r = walk(v, path);
                path.pop();
                r
            }),
            _ => None,
        }
    }
    walk(&toml::Value::Table(table.clone()), &mut Vec::new())
}

/// The 1-based line where `key` (a path like `["camera", "fov"]` or `["light", "2", "radius"]`;
/// array indices after the key are ignored) is set in `text`: the line `key = ...` inside the
/// table `[camera]`, or the `n`-th `[[light]]`. `None` if not found (e.g. an inline table).
pub fn key_line(text: &str, key: &[&str]) -> Option<usize> {
    let nested;
    let (table, rest): (Vec<&str>, &[&str]) = match key {
        [t, i, rest @ ..] if i.parse::<usize>().is_ok() => (vec![t, i], rest),
        // `[[camera.key]]`: an array of tables inside a table.
        [t, sub, i, rest @ ..] if !rest.is_empty() && i.parse::<usize>().is_ok() => {
            nested = format!("{t}.{sub}");
            (vec![nested.as_str(), i], rest)
        }
        [t, rest @ ..] if !rest.is_empty() => (vec![t], rest),
        _ => (vec![], key),
    };
    let name = rest.first().copied()?;
    let mut current: Vec<String> = Vec::new();
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    for (n, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix("[[").and_then(|h| h.split("]]").next()) {
            let h = h.trim().to_string();
            let c = counts.entry(h.clone()).or_insert(0);
            current = vec![h, c.to_string()];
            *c += 1;
        } else if let Some(h) = l.strip_prefix('[').and_then(|h| h.split(']').next()) {
            current = vec![h.trim().to_string()];
        } else if current.iter().map(String::as_str).eq(table.iter().copied())
            && let Some(after) = l.strip_prefix(name)
            && after.trim_start().starts_with('=')
        {
            return Some(n + 1);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_bad_floats_and_their_lines() {
        let text = "[camera]\nfov = 40\n\n[[light]]\nradius = 1\n[[light]]\nposition = [0, inf, 0]\nradius = nan\n";
        let t: toml::Table = text.parse().unwrap();
        let (path, v) = bad_float(&t).unwrap();
        assert!(v.is_nan() || v.is_infinite(), "{path:?}");
        assert_eq!(key_line(text, &["light", "1", "radius"]), Some(8));
        assert_eq!(key_line(text, &["light", "1", "position", "1"]), Some(7));
        assert_eq!(key_line(text, &["light", "0", "radius"]), Some(5));
        assert_eq!(key_line(text, &["camera", "fov"]), Some(2));
        assert_eq!(key_line(text, &["camera", "aperture"]), None);
        let keys =
            "[camera]\nfov = 30\n[[camera.key]]\nframe = 0\n[[camera.key]]\nframe = 9\nfov = nan\n";
        assert_eq!(key_line(keys, &["camera", "key", "1", "fov"]), Some(7));
        assert_eq!(key_line(keys, &["camera", "fov"]), Some(2));
        // An array's element index after a key is not a table's index.
        let pos = "[camera]\nfov = 30\nposition = [nan, 0.5, 4.0]\n";
        assert_eq!(key_line(pos, &["camera", "position", "0"]), Some(3));
        let ok: toml::Table = "a = 1.5\nb = [1e38]\n".parse().unwrap();
        assert!(bad_float(&ok).is_none());
        let big: toml::Table = "[film]\nior = 1e39\n".parse().unwrap();
        assert_eq!(bad_float(&big).unwrap().0, vec!["film", "ior"]);
    }
}
