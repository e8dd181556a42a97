//! `[[camera.key]]`: the keys of a sequence's camera path, and their checks at parse (in
//! increasing frame order, no frame twice, each optional key given in every key or in none),
//! so a bad path is refused before anything loads, naming the file and the key's line.

use serde::Deserialize;

/// One key of a camera path: where the camera is at frame `frame` of a sequence. Between keys
/// positions and look-at points follow a natural cubic spline through the keys (continuous
/// velocity), the scalars ease (smoothstep); before the first key and after the last the
/// camera holds. See [`crate::pipeline::camera_path`].
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// The sequence's frame number this key holds at.
    pub frame: u64,
    /// Eye position, scene units (required).
    pub position: [f32; 3],
    /// Point looked at, scene units (default: the sequence's auto-framed look-at point).
    pub look_at: Option<[f32; 3]>,
    /// Vertical field of view, degrees (default: `[camera] fov`).
    pub fov: Option<f32>,
    /// Thin-lens aperture radius, scene units (default: `[camera] aperture`).
    pub aperture: Option<f32>,
    /// Distance in focus, scene units (default: `[camera] focus_distance`).
    pub focus_distance: Option<f32>,
    /// Exposure, EV (default: `[output] exposure`).
    pub exposure: Option<f32>,
    /// Line of this key's `[[camera.key]]` header (filled in by the parser; 0 when built in
    /// code).
    #[serde(skip)]
    pub line: usize,
}

impl CameraKey {
    /// `key` at `line`, for messages: `camera.key (line 12)` or `camera.key at frame 3`.
    fn name(&self) -> String {
        if self.line > 0 {
            format!("line {}: camera.key", self.line)
        } else {
            format!("camera.key at frame {}", self.frame)
        }
    }

    /// Which optional keys this key gives, in the order of [`OPTIONAL`].
    fn given(&self) -> [bool; 5] {
        [
            self.look_at.is_some(),
            self.fov.is_some(),
            self.aperture.is_some(),
            self.focus_distance.is_some(),
            self.exposure.is_some(),
        ]
    }
}

/// The optional keys of a camera key, in the order of [`CameraKey::given`].
const OPTIONAL: [&str; 5] = ["look_at", "fov", "aperture", "focus_distance", "exposure"];

/// Fills in each key's line: the n-th `[[camera.key]]` header of `text` is the n-th key's.
pub(super) fn number_lines(keys: &mut [CameraKey], text: &str) {
    let headers = text
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            l.trim()
                .strip_prefix("[[")
                .and_then(|h| h.split("]]").next())
                .is_some_and(|h| h.trim() == "camera.key")
        })
        .map(|(n, _)| n + 1);
    for (k, line) in keys.iter_mut().zip(headers) {
        k.line = line;
    }
}

/// Checks a camera path: frames strictly increasing (a key out of order or a frame given
/// twice is refused), each optional key (look_at, fov, aperture, focus_distance, exposure)
/// given in every key or in none (so every span between keys has both ends), fov within
/// 1..170 degrees, aperture >= 0, focus_distance > 0. Floats are checked finite by the parser.
///
/// # Errors
/// A message naming the key (its line when parsed from a file) and the problem.
pub fn check_keys(keys: &[CameraKey]) -> std::result::Result<(), String> {
    for pair in keys.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if b.frame == a.frame {
            return Err(format!(
                "{}: frame {} is keyed twice (keys hold one camera per frame)",
                b.name(),
                b.frame
            ));
        }
        if b.frame < a.frame {
            return Err(format!(
                "{}: frame {} comes after frame {} (keys must be in increasing frame order)",
                b.name(),
                b.frame,
                a.frame
            ));
        }
    }
    let Some(first) = keys.first() else {
        return Ok(());
    };
    for k in keys {
        if let Some(i) = (0..OPTIONAL.len()).find(|&i| k.given()[i] != first.given()[i]) {
            let (with, without) = if first.given()[i] {
                (first, k)
            } else {
                (k, first)
            };
            return Err(format!(
                "{}: {} is given at frame {} but not at frame {} (give it in every key or in \
                 none)",
                k.name(),
                OPTIONAL[i],
                with.frame,
                without.frame
            ));
        }
        if let Some(f) = k.fov.filter(|f| !(1.0..=170.0).contains(f)) {
            return Err(format!("{}: fov must be 1..170 degrees, got {f}", k.name()));
        }
        if let Some(a) = k.aperture.filter(|a| *a < 0.0) {
            return Err(format!("{}: aperture must be >= 0, got {a}", k.name()));
        }
        if let Some(f) = k.focus_distance.filter(|f| *f <= 0.0) {
            return Err(format!("{}: focus_distance must be > 0, got {f}", k.name()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(frame: u64) -> CameraKey {
        CameraKey {
            frame,
            position: [0.0, 0.0, 5.0],
            ..CameraKey::default()
        }
    }

    #[test]
    fn refuses_keys_out_of_order_twice_or_half_given() {
        assert!(check_keys(&[key(0), key(10), key(30)]).is_ok());
        let e = check_keys(&[key(0), key(10), key(10)]).unwrap_err();
        assert!(e.contains("keyed twice") && e.contains("frame 10"), "{e}");
        let e = check_keys(&[key(0), key(20), key(10)]).unwrap_err();
        assert!(e.contains("increasing") && e.contains("frame 10"), "{e}");
        let mut half = [key(0), key(10)];
        half[1].fov = Some(30.0);
        let e = check_keys(&half).unwrap_err();
        assert!(
            e.contains("fov is given at frame 10 but not at frame 0"),
            "{e}"
        );
        let mut wide = [key(0)];
        wide[0].fov = Some(200.0);
        assert!(check_keys(&wide).unwrap_err().contains("1..170"));
    }
}
