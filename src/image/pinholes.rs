//! The pinhole metric: the share of a film's interior where a camera ray misses the first film
//! layer — it meets no film at all, or its first crossing lies far behind its neighbours' (it
//! slipped between the front layer's splats and found the back of the bubble).
//!
//! From a depth buffer (distance to the first crossing, 0 where none): a pixel is **interior**
//! if within [`REACH`] pixels in each of the four axis directions there is a hit (so the
//! silhouette's outside and holes wider than 2·[`REACH`] px are not interior — real holes stay
//! holes). An interior pixel is **missing** if it has no hit, or its depth lies behind the
//! median m of the hits in its 5×5 neighbourhood by more than ([`BEHIND`] − 1)·m and more than
//! [`SPREAD`] × their median absolute deviation (near a silhouette, where the front layer is
//! seen at grazing angles, depth varies that much from pixel to pixel without any hole).

/// How far (pixels) a hit must be found in each direction for a pixel to be interior.
pub const REACH: usize = 3;

/// A first crossing this many times the local median depth away is behind the front layer.
pub const BEHIND: f32 = 1.05;

/// ... and at least this many median absolute deviations of the local depths behind it.
pub const SPREAD: f32 = 4.0;

/// Counts of [`missing_front_layer`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrontLayer {
    /// Interior pixels.
    pub interior: usize,
    /// Interior pixels whose first film layer is missing.
    pub missing: usize,
}

impl FrontLayer {
    /// Missing share of the interior, percent (0 for no interior).
    pub fn percent(&self) -> f64 {
        if self.interior == 0 {
            0.0
        } else {
            100.0 * self.missing as f64 / self.interior as f64
        }
    }
}

/// The pinhole metric of a `width × height` depth buffer (row-major, 0 = no hit).
/// Cost: O(pixels × 25).
///
/// ```
/// use filmsplat::image::pinholes::missing_front_layer;
/// let mut depth = vec![1.0f32; 20 * 20];
/// depth[10 * 20 + 10] = 0.0; // a pinhole
/// depth[5 * 20 + 5] = 3.0; // a ray that found the back layer
/// let f = missing_front_layer(&depth, 20, 20);
/// assert_eq!(f.missing, 2);
/// assert_eq!(f.interior, 18 * 18); // every pixel with a hit 1..=3 px away on all four sides
/// ```
pub fn missing_front_layer(depth: &[f32], width: usize, height: usize) -> FrontLayer {
    missing_front_layer_besides(depth, width, height, &[])
}

/// [`missing_front_layer`] of the film alone, where the pixels flagged in `other` (e.g. those
/// covered by droplets; empty = none) hold something else in front: they are neither film
/// hits nor counted, and their depths are not used as neighbours'.
pub fn missing_front_layer_besides(
    depth: &[f32],
    width: usize,
    height: usize,
    other: &[bool],
) -> FrontLayer {
    let (interior, missing) = missing_pixels(depth, width, height, other);
    FrontLayer {
        interior,
        missing: missing.len(),
    }
}

/// What [`missing_front_layer_besides`] counts: the number of interior pixels, and the
/// missing ones (row-major indices, ascending), for a caller that looks at each (e.g. asks
/// whether the particles hold film there).
pub fn missing_pixels(
    depth: &[f32],
    width: usize,
    height: usize,
    other: &[bool],
) -> (usize, Vec<usize>) {
    let mut out = (0, Vec::new());
    if depth.len() != width * height || !(other.is_empty() || other.len() == depth.len()) {
        return out;
    }
    let skip = |k: usize| other.get(k).copied().unwrap_or(false);
    let hit = |x: usize, y: usize| depth[y * width + x] > 0.0 && !skip(y * width + x);
    let mut near = Vec::with_capacity(25);
    for y in 0..height {
        for x in 0..width {
            let found = |dx: isize, dy: isize| {
                (1..=REACH as isize).any(|s| {
                    let (xx, yy) = (x as isize + dx * s, y as isize + dy * s);
                    xx >= 0
                        && yy >= 0
                        && (xx as usize) < width
                        && (yy as usize) < height
                        && hit(xx as usize, yy as usize)
                })
            };
            if skip(y * width + x) || !(found(1, 0) && found(-1, 0) && found(0, 1) && found(0, -1))
            {
                continue;
            }
            out.0 += 1;
            let d = depth[y * width + x];
            if d <= 0.0 {
                out.1.push(y * width + x);
                continue;
            }
            near.clear();
            for yy in y.saturating_sub(2)..(y + 3).min(height) {
                for xx in x.saturating_sub(2)..(x + 3).min(width) {
                    let v = depth[yy * width + xx];
                    if v > 0.0 && !skip(yy * width + xx) {
                        near.push(v);
                    }
                }
            }
            let mid = near.len() / 2;
            let median = *near.select_nth_unstable_by(mid, f32::total_cmp).1;
            near.iter_mut().for_each(|v| *v = (*v - median).abs());
            let mad = *near.select_nth_unstable_by(mid, f32::total_cmp).1;
            if d - median > ((BEHIND - 1.0) * median).max(SPREAD * mad) {
                out.1.push(y * width + x);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_of_something_else_are_neither_film_nor_holes() {
        // A film at depth 1 with a 3×3 droplet in front (depth 0.3): no hole; scattered
        // droplets over no film: no interior at all.
        let (w, h) = (20, 20);
        let mut depth = vec![1.0f32; w * h];
        let mut other = vec![false; w * h];
        for y in 8..11 {
            for x in 8..11 {
                depth[y * w + x] = 0.3;
                other[y * w + x] = true;
            }
        }
        let all = missing_front_layer(&depth, w, h);
        let film = missing_front_layer_besides(&depth, w, h, &other);
        assert_eq!(film.missing, 0);
        // Not interior: the droplet's 9 pixels, and the 3 beside each of its sides, which see
        // no film within REACH = 3 px across it.
        assert_eq!(film.interior, all.interior - 9 - 4 * 3);
        assert!(all.missing == 0, "the near droplet is not behind");
        let mut drops = vec![0.0f32; w * h];
        let mut flag = vec![false; w * h];
        for k in (0..w * h).step_by(3) {
            drops[k] = 0.5;
            flag[k] = true;
        }
        assert!(
            missing_front_layer(&drops, w, h).missing > 0,
            "as film: holes"
        );
        let none = missing_front_layer_besides(&drops, w, h, &flag);
        assert_eq!((none.interior, none.missing), (0, 0));
    }
}
