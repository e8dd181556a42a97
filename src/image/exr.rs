//! OpenEXR output of the render with its auxiliary layers, and RGBA input (for tests and
//! lat-long environment maps).
//!
//! Files are single-part scan-line EXRs, ZIP16-compressed, all channels 32-bit float, using the
//! usual `layer.channel` naming so that Nuke, Blender, OpenImageIO etc. show named layers:
//!
//! | channels | content |
//! |---|---|
//! | `R`, `G`, `B`, `A` | linear colour and coverage (main layer) |
//! | `depth.Z` | depth per pixel, as given by the caller (the renderer's units; +Inf = no hit) |
//! | `normal.X`, `normal.Y`, `normal.Z` | surface normal per pixel |
//! | `thickness.Y` | film thickness per pixel, nanometres |
//! | `hits.Y` | number of film crossings per pixel |
//! | `droplets.Y` | share of the pixel covered by droplets (0..1; also counted in `A`) |

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use ::exr::prelude as x;
use x::{ReadChannels, ReadLayers, WritableImage};

use crate::atomic::write_atomic;
use crate::{Error, Result};

/// Channel name of the depth layer.
pub const DEPTH_CHANNEL: &str = "depth.Z";
/// Channel names of the normal layer.
pub const NORMAL_CHANNELS: [&str; 3] = ["normal.X", "normal.Y", "normal.Z"];
/// Channel name of the film-thickness layer (nm).
pub const THICKNESS_CHANNEL: &str = "thickness.Y";
/// Channel name of the hit-count layer.
pub const HITS_CHANNEL: &str = "hits.Y";
/// Channel name of the droplet-coverage layer.
pub const DROPLETS_CHANNEL: &str = "droplets.Y";

/// The layers of one EXR file. Every present buffer has `width * height` entries, row-major,
/// top row first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExrLayers {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Linear RGB and alpha (channels `R`, `G`, `B`, `A`).
    pub rgba: Vec<[f32; 4]>,
    /// Depth (channel `depth.Z`).
    pub depth: Option<Vec<f32>>,
    /// Normal (channels `normal.X/Y/Z`).
    pub normal: Option<Vec<[f32; 3]>>,
    /// Film thickness in nm (channel `thickness.Y`).
    pub thickness: Option<Vec<f32>>,
    /// Hit count (channel `hits.Y`).
    pub hit_count: Option<Vec<f32>>,
    /// Droplet coverage, 0..1 (channel `droplets.Y`).
    pub droplets: Option<Vec<f32>>,
}

impl ExrLayers {
    /// An RGBA-only set of layers.
    pub fn rgba(width: usize, height: usize, rgba: Vec<[f32; 4]>) -> Self {
        ExrLayers {
            width,
            height,
            rgba,
            ..Default::default()
        }
    }

    fn check(&self) -> std::result::Result<(), String> {
        let n = self
            .width
            .checked_mul(self.height)
            .ok_or("image size overflows")?;
        if n == 0 {
            return Err(format!(
                "cannot write a {} x {} image",
                self.width, self.height
            ));
        }
        let lens = [
            ("rgba", Some(self.rgba.len())),
            ("depth", self.depth.as_ref().map(Vec::len)),
            ("normal", self.normal.as_ref().map(Vec::len)),
            ("thickness", self.thickness.as_ref().map(Vec::len)),
            ("hit_count", self.hit_count.as_ref().map(Vec::len)),
            ("droplets", self.droplets.as_ref().map(Vec::len)),
        ];
        for (name, len) in lens {
            if let Some(len) = len.filter(|&l| l != n) {
                return Err(format!(
                    "{name} layer has {len} pixels, expected {} x {}",
                    self.width, self.height
                ));
            }
        }
        Ok(())
    }
}

fn map_exr_err(path: &Path, e: x::Error) -> Error {
    match e {
        x::Error::Io(io) => Error::io(path, io),
        other => Error::Format {
            path: path.into(),
            format: "EXR",
            message: other.to_string(),
        },
    }
}

/// Writes `layers` to `path` as an EXR (channel names in the module docs). Atomic: no partial
/// file is left on error. Cost: ZIP compression, roughly 20-50 ns per pixel and channel.
pub fn write_exr(path: &Path, layers: &ExrLayers) -> Result<()> {
    layers.check().map_err(|message| Error::Format {
        path: path.into(),
        format: "EXR",
        message,
    })?;
    let chan = |name: &str, v: Vec<f32>| x::AnyChannel::new(name, x::FlatSamples::F32(v));
    let comp = |i: usize| layers.rgba.iter().map(|p| p[i]).collect::<Vec<f32>>();
    let mut list: x::SmallVec<[x::AnyChannel<x::FlatSamples>; 4]> = x::SmallVec::new();
    for (i, name) in ["R", "G", "B", "A"].into_iter().enumerate() {
        list.push(chan(name, comp(i)));
    }
    if let Some(d) = &layers.depth {
        list.push(chan(DEPTH_CHANNEL, d.clone()));
    }
    if let Some(n) = &layers.normal {
        for (i, name) in NORMAL_CHANNELS.into_iter().enumerate() {
            list.push(chan(name, n.iter().map(|p| p[i]).collect()));
        }
    }
    if let Some(t) = &layers.thickness {
        list.push(chan(THICKNESS_CHANNEL, t.clone()));
    }
    if let Some(h) = &layers.hit_count {
        list.push(chan(HITS_CHANNEL, h.clone()));
    }
    if let Some(d) = &layers.droplets {
        list.push(chan(DROPLETS_CHANNEL, d.clone()));
    }
    let layer = x::Layer::new(
        (layers.width, layers.height),
        x::LayerAttributes::default(),
        x::Encoding::SMALL_LOSSLESS,
        x::AnyChannels::sort(list),
    );
    let image = x::Image::from_layer(layer);
    write_atomic(path, |w| {
        image
            .write()
            .to_buffered(w)
            .map_err(|e| map_exr_err(path, e))
    })
}

/// Largest ratio of an EXR's pixel bytes to its file size ZIP, PXR24 and B44 reach (deflate's
/// limit, with a margin).
const MAX_EXR_RATIO: u64 = 1100;

/// Reads only the headers and refuses an image whose declared size cannot be in the file (more
/// pixel bytes than the file could decompress to) or would not fit in memory (its samples as
/// f32, twice: the decoder's copy and ours), before the decoder allocates anything for it.
fn check_declared_size(path: &Path) -> Result<()> {
    // A pipe would block the open and a device never ends: only regular files.
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(Error::Format {
            path: path.to_path_buf(),
            format: "EXR",
            message: "not a regular file".into(),
        });
    }
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let file_bytes = file.metadata().map(|m| m.len()).unwrap_or(0);
    let meta = ::exr::meta::MetaData::read_from_buffered(BufReader::new(file), false)
        .map_err(|e| map_exr_err(path, e))?;
    let invalid = |message: String| Error::Format {
        path: path.to_path_buf(),
        format: "EXR",
        message,
    };
    for h in meta.headers.iter() {
        let (w, hgt) = (h.layer_size.0 as u64, h.layer_size.1 as u64);
        let pixels = w.saturating_mul(hgt);
        let stored: u64 = h
            .channels
            .list
            .iter()
            .map(|c| match c.sample_type {
                ::exr::meta::attribute::SampleType::F16 => 2u64,
                _ => 4,
            })
            .sum();
        let stored_bytes = pixels.saturating_mul(stored);
        // The best ratio each compression reaches; PIZ (run-length Huffman) and the lossy DWA
        // have no useful bound, so only the memory check below applies to them.
        use ::exr::compression::Compression as C;
        let ratio = match h.compression {
            C::Uncompressed => Some(1),
            C::RLE => Some(128),
            C::ZIP1 | C::ZIP16 | C::PXR24 | C::B44 | C::B44A => Some(MAX_EXR_RATIO),
            _ => None,
        };
        if let Some(ratio) = ratio
            && stored_bytes > file_bytes.saturating_mul(ratio).saturating_add(1 << 16)
        {
            return Err(invalid(format!(
                "the header declares {w}x{hgt} pixels ({stored_bytes} bytes of samples), more \
                 than its {file_bytes} bytes can hold"
            )));
        }
        let f32_bytes = pixels.saturating_mul(4 * h.channels.list.len() as u64);
        crate::budget::check(f32_bytes.saturating_mul(2), || {
            format!("a {w}x{hgt} image of {} channels", h.channels.list.len())
        })
        .map_err(invalid)?;
    }
    Ok(())
}

/// The first layer of an EXR file with all its channels as f32.
struct Channels {
    width: usize,
    height: usize,
    list: Vec<(String, Vec<f32>)>,
}

impl Channels {
    fn read(path: &Path) -> Result<Self> {
        check_declared_size(path)?;
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        let image = x::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_buffered(BufReader::new(file))
            .map_err(|e| map_exr_err(path, e))?;
        let layer = image.layer_data;
        let list = layer
            .channel_data
            .list
            .iter()
            .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
            .collect();
        Ok(Channels {
            width: layer.size.0,
            height: layer.size.1,
            list,
        })
    }

    fn get(&self, name: &str) -> Option<&[f32]> {
        self.list
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// The colour channels: `R,G,B[,A]`, else the first `prefix.R/G/B[/A]` group, else a
    /// luminance-only `Y` channel as grey. Missing alpha is 1.
    fn colour(&self, path: &Path) -> Result<Vec<[f32; 4]>> {
        let mut prefixes = vec![String::new()];
        for (n, _) in &self.list {
            if let Some(p) = n.strip_suffix(".R") {
                prefixes.push(format!("{p}."));
            }
        }
        for p in &prefixes {
            let get = |c: &str| self.get(&format!("{p}{c}"));
            if let (Some(r), Some(g), Some(b)) = (get("R"), get("G"), get("B")) {
                let a = get("A");
                return Ok((0..r.len())
                    .map(|i| [r[i], g[i], b[i], a.map_or(1.0, |a| a[i])])
                    .collect());
            }
        }
        if let Some(y) = self.get("Y") {
            let a = self.get("A");
            return Ok((0..y.len())
                .map(|i| [y[i], y[i], y[i], a.map_or(1.0, |a| a[i])])
                .collect());
        }
        let names: Vec<&str> = self.list.iter().map(|(n, _)| n.as_str()).collect();
        Err(Error::Format {
            path: path.into(),
            format: "EXR",
            message: format!("no R, G, B (or Y) channels; channels are {names:?}"),
        })
    }
}

/// Reads the colour of an EXR: returns `(width, height, rgba)`, top row first.
///
/// Accepts any RGB(A) EXR (half, float or uint samples; first layer; `R,G,B[,A]` or a
/// `layer.R/G/B[/A]` group or luminance `Y`). Missing alpha is 1. Suitable for lat-long
/// environment maps.
pub fn read_exr_rgba(path: &Path) -> Result<(usize, usize, Vec<[f32; 4]>)> {
    let ch = Channels::read(path)?;
    let rgba = ch.colour(path)?;
    Ok((ch.width, ch.height, rgba))
}

/// Reads an EXR written by [`write_exr`] (or any RGB(A) EXR) including the named auxiliary
/// layers that are present.
pub fn read_exr(path: &Path) -> Result<ExrLayers> {
    let ch = Channels::read(path)?;
    let rgba = ch.colour(path)?;
    let normal = match NORMAL_CHANNELS.map(|n| ch.get(n)) {
        [Some(nx), Some(ny), Some(nz)] => {
            Some((0..nx.len()).map(|i| [nx[i], ny[i], nz[i]]).collect())
        }
        _ => None,
    };
    Ok(ExrLayers {
        width: ch.width,
        height: ch.height,
        rgba,
        depth: ch.get(DEPTH_CHANNEL).map(<[f32]>::to_vec),
        normal,
        thickness: ch.get(THICKNESS_CHANNEL).map(<[f32]>::to_vec),
        hit_count: ch.get(HITS_CHANNEL).map(<[f32]>::to_vec),
        droplets: ch.get(DROPLETS_CHANNEL).map(<[f32]>::to_vec),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("filmsplat-exr-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn sample(w: usize, h: usize) -> ExrLayers {
        let n = w * h;
        let f = |i: usize, k: f32| (i as f32 * 0.37 + k).sin() * 10.0;
        ExrLayers {
            width: w,
            height: h,
            rgba: (0..n)
                .map(|i| [f(i, 0.0), f(i, 1.0), f(i, 2.0), (i % 3) as f32 * 0.5])
                .collect(),
            depth: Some(
                (0..n)
                    .map(|i| {
                        if i == 3 {
                            f32::INFINITY
                        } else {
                            i as f32 * 1.5
                        }
                    })
                    .collect(),
            ),
            normal: Some((0..n).map(|i| [f(i, 3.0), f(i, 4.0), -1.0]).collect()),
            thickness: Some((0..n).map(|i| 200.0 + i as f32).collect()),
            hit_count: Some((0..n).map(|i| (i % 5) as f32).collect()),
            droplets: Some((0..n).map(|i| (i % 4) as f32 * 0.25).collect()),
        }
    }

    #[test]
    fn round_trip_with_all_layers() {
        let d = scratch("rt");
        let p = d.join("a.exr");
        let layers = sample(7, 5); // odd sizes: rows and columns not interchangeable
        write_exr(&p, &layers).unwrap();
        let back = read_exr(&p).unwrap();
        assert_eq!(back, layers);
        let (w, h, rgba) = read_exr_rgba(&p).unwrap();
        assert_eq!((w, h), (7, 5));
        assert_eq!(rgba, layers.rgba);
        // Only the colour layers: the optional ones read back as absent.
        let plain = ExrLayers::rgba(2, 3, vec![[0.25, 0.5, 1.0, 1.0]; 6]);
        write_exr(&p, &plain).unwrap();
        assert_eq!(read_exr(&p).unwrap(), plain);
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn rgb_without_alpha_reads_alpha_one() {
        let d = scratch("rgb");
        let p = d.join("env.exr");
        let px = |x: usize, y: usize| (x as f32, y as f32, 0.5f32);
        x::write_rgb_file(&p, 4, 2, px).unwrap();
        let (w, h, rgba) = read_exr_rgba(&p).unwrap();
        assert_eq!((w, h), (4, 2));
        assert_eq!(rgba[4 + 3], [3.0, 1.0, 0.5, 1.0]); // row 1, column 3
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn errors_name_the_file_and_leave_nothing() {
        let d = scratch("err");
        let p = d.join("missing-dir/out.exr");
        let e = write_exr(&p, &sample(2, 2)).unwrap_err();
        assert!(e.to_string().contains("missing-dir/out.exr"), "{e}");
        assert!(!p.exists());
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);

        let mut bad = sample(3, 3);
        bad.thickness.as_mut().unwrap().pop();
        let q = d.join("bad.exr");
        let e = write_exr(&q, &bad).unwrap_err();
        assert!(
            e.to_string().contains("thickness") && e.to_string().contains("bad.exr"),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);

        std::fs::write(&q, b"not an exr").unwrap();
        let e = read_exr_rgba(&q).unwrap_err();
        assert!(e.to_string().contains("bad.exr"), "{e}");
        assert!(read_exr_rgba(&d.join("nope.exr")).is_err());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
