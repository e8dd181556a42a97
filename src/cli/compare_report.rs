//! The report of `filmsplat compare`: each side's figures and the metrics, as text or as the
//! `--json` object (written by serde_json).

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use crate::image::RgbImage;
use crate::pipeline::compare::Metrics;

/// One side's figures.
#[derive(Debug)]
pub(super) struct Side {
    pub(super) label: String,
    pub(super) elements: usize,
    pub(super) prepare: Duration,
    pub(super) mesh: Option<Duration>,
    pub(super) meshing: Option<Duration>,
    pub(super) render: Duration,
}

/// One compared frame.
pub(super) struct FrameResult {
    pub(super) frame: Option<u64>,
    pub(super) sides: [Side; 2],
    pub(super) metrics: Metrics,
    pub(super) images: [RgbImage; 2],
    pub(super) output: PathBuf,
}

/// `x` rounded to `decimals` places (the JSON report's precision), `None` (null) if not finite.
fn rounded(x: f64, decimals: i32) -> Option<f64> {
    let scale = 10f64.powi(decimals);
    x.is_finite().then(|| (x * scale).round() / scale)
}

/// Seconds to 0.1 ms.
fn secs(d: Duration) -> Option<f64> {
    rounded(d.as_secs_f64(), 4)
}

/// One side of a comparison in the `--json` report.
#[derive(serde::Serialize)]
struct SideJson<'a> {
    geometry: &'a str,
    elements: usize,
    prepare_s: Option<f64>,
    mesh_s: Option<f64>,
    meshing_s: Option<f64>,
    render_s: Option<f64>,
}

impl<'a> From<&'a Side> for SideJson<'a> {
    fn from(s: &'a Side) -> Self {
        SideJson {
            geometry: &s.label,
            elements: s.elements,
            prepare_s: secs(s.prepare),
            mesh_s: s.mesh.and_then(secs),
            meshing_s: s.meshing.and_then(secs),
            render_s: secs(s.render),
        }
    }
}

/// The CIEDE2000 summary, to 6 decimals.
#[derive(serde::Serialize)]
struct DeltaEJson {
    mean: Option<f64>,
    p95: Option<f64>,
    max: Option<f64>,
}

/// One compared frame (or the one comparison) in the `--json` report.
#[derive(serde::Serialize)]
struct FrameJson<'a> {
    #[serde(skip_serializing_if = "Option::is_none")]
    frame: Option<u64>,
    a: SideJson<'a>,
    b: SideJson<'a>,
    /// PSNR, dB; null for identical pictures.
    psnr_db: Option<f64>,
    identical: bool,
    ssim: Option<f64>,
    delta_e: DeltaEJson,
    output: String,
}

impl<'a> FrameJson<'a> {
    /// `r`, with its frame number if it is one of a sequence (`frame`).
    fn new(r: &'a FrameResult, frame: Option<u64>) -> Self {
        let m = &r.metrics;
        FrameJson {
            frame,
            a: (&r.sides[0]).into(),
            b: (&r.sides[1]).into(),
            psnr_db: rounded(m.psnr_db, 6),
            identical: m.psnr_db.is_infinite(),
            ssim: rounded(m.ssim, 6),
            delta_e: DeltaEJson {
                mean: rounded(m.delta_e.mean, 6),
                p95: rounded(m.delta_e.p95, 6),
                max: rounded(m.delta_e.max, 6),
            },
            output: r.output.display().to_string(),
        }
    }
}

/// A sequence's `--json` report: its frames and the flicker of each side.
#[derive(serde::Serialize)]
struct SequenceJson<'a> {
    frames: Vec<FrameJson<'a>>,
    temporal_delta_e: Option<TemporalJson>,
}

/// Mean ΔE2000 between adjacent frames, per side.
#[derive(serde::Serialize)]
struct TemporalJson {
    a: Option<f64>,
    b: Option<f64>,
}

/// Prints the metrics (text or JSON) of one comparison or a sequence of them.
pub(super) fn report(
    json: bool,
    quiet: bool,
    results: &[FrameResult],
    temporal: Option<[f64; 2]>,
    out: &mut dyn Write,
) {
    if json {
        let _ = writeln!(out, "{}", report_json(results, temporal));
        return;
    }
    if quiet {
        return;
    }
    for r in results {
        if let Some(f) = r.frame {
            let _ = writeln!(out, "frame {f}:");
        }
        for (k, s) in r.sides.iter().enumerate() {
            let mut line = format!(
                "  {}: {} ({} elements): prepare {:.3} s",
                ["A", "B"][k],
                s.label,
                s.elements,
                s.prepare.as_secs_f64()
            );
            if let Some(m) = s.meshing {
                line += &format!(", meshing {:.3} s", m.as_secs_f64());
            }
            if let Some(m) = s.mesh {
                line += &format!(", mesh prep {:.3} s", m.as_secs_f64());
            }
            line += &format!(", render {:.3} s", s.render.as_secs_f64());
            let _ = writeln!(out, "{line}");
        }
        let m = &r.metrics;
        let _ = writeln!(
            out,
            "  PSNR {} dB, SSIM {:.4}, ΔE2000 mean {:.3}, p95 {:.3}, max {:.3}; wrote {}",
            if m.psnr_db.is_infinite() {
                "inf".to_string()
            } else {
                format!("{:.2}", m.psnr_db)
            },
            m.ssim,
            m.delta_e.mean,
            m.delta_e.p95,
            m.delta_e.max,
            r.output.display()
        );
    }
    if let Some(t) = temporal {
        let _ = writeln!(
            out,
            "temporal stability (mean ΔE2000 between adjacent frames): A {:.3}, B {:.3}",
            t[0], t[1]
        );
    }
}

/// The `--json` report: one object for a single comparison, else the frames and the flicker.
fn report_json(results: &[FrameResult], temporal: Option<[f64; 2]>) -> String {
    let text = if let [r] = results
        && r.frame.is_none()
    {
        serde_json::to_string(&FrameJson::new(r, None))
    } else {
        serde_json::to_string(&SequenceJson {
            frames: results
                .iter()
                .map(|r| FrameJson::new(r, Some(r.frame.unwrap_or(0))))
                .collect(),
            temporal_delta_e: temporal.map(|t| TemporalJson {
                a: rounded(t[0], 6),
                b: rounded(t[1], 6),
            }),
        })
    };
    // Strings, numbers and options only: serialising cannot fail.
    text.unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::metrics::DeltaEStats;

    fn result(frame: Option<u64>, output: &str, psnr_db: f64) -> FrameResult {
        let side = |label: &str| Side {
            label: label.to_string(),
            elements: 7,
            prepare: Duration::from_micros(123_456),
            mesh: None,
            meshing: Some(Duration::from_millis(2)),
            render: Duration::from_secs(1),
        };
        FrameResult {
            frame,
            sides: [side("disk"), side("mesh \"a\\b\"")],
            metrics: Metrics {
                psnr_db,
                ssim: 0.123_456_789,
                delta_e: DeltaEStats {
                    mean: 1.0,
                    p95: 2.5,
                    max: f64::NAN,
                },
                delta_e_map: Vec::new(),
            },
            images: [RgbImage::new(0, 0), RgbImage::new(0, 0)],
            output: PathBuf::from(output),
        }
    }

    /// Paths and labels needing escaping (quote, backslash, control character, non-ASCII)
    /// come back intact; numbers keep the report's precision; non-finite ones are null.
    #[test]
    fn json_escapes_and_parses_back() {
        let path = "out \"x\"\\é\u{1}\n.png";
        let v: serde_json::Value =
            serde_json::from_str(&report_json(&[result(None, path, f64::INFINITY)], None)).unwrap();
        assert_eq!(v["output"], path);
        assert_eq!(v["b"]["geometry"], "mesh \"a\\b\"");
        assert_eq!(v["a"]["prepare_s"], 0.1235);
        assert_eq!(v["a"]["mesh_s"], serde_json::Value::Null);
        assert_eq!(v["a"]["meshing_s"], 0.002);
        assert_eq!(
            (v["psnr_db"].is_null(), &v["identical"]),
            (true, &true.into())
        );
        assert_eq!(v["ssim"], 0.123457);
        assert_eq!(
            v["delta_e"],
            serde_json::json!({"mean": 1.0, "p95": 2.5, "max": null})
        );
        assert!(v.get("frame").is_none());
        let seq = [
            result(Some(3), "a.png", 30.0),
            result(Some(4), "b.png", 31.0),
        ];
        let v: serde_json::Value =
            serde_json::from_str(&report_json(&seq, Some([0.5, f64::NAN]))).unwrap();
        assert_eq!(v["frames"][1]["frame"], 4);
        assert_eq!(v["frames"][0]["identical"], false);
        assert_eq!(
            v["temporal_delta_e"],
            serde_json::json!({"a": 0.5, "b": null})
        );
    }
}
