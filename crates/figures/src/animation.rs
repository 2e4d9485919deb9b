//! Animated GIFs at a fraction of plotters' own cost.
//!
//! plotters' GIF backend draws frames one after the other and runs a NeuQuant colour
//! quantization on every frame, which cost more than the physics of a run. Here:
//!
//! - frames are drawn in parallel (rayon) into RGB buffers, a batch at a time so that
//!   memory stays bounded;
//! - one palette serves the whole animation, learnt once from the first and last
//!   frames (every frame shows the same bodies, axes and fonts, so the same colours),
//!   and each pixel is mapped to it through a cache of the colours already seen;
//! - each frame after the first stores only the rectangle that changed since the
//!   previous one (the axes and the floor do not move), which the encoder compresses.

use crate::plot::{register_font, Canvas};
use crate::{err, file, write_error, FigureError, Result};
use color_quant::NeuQuant;
use plotters::prelude::*;
use rayon::prelude::*;
use std::borrow::Cow;
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

/// Frames drawn together before they are encoded (bounds the memory held).
const BATCH: usize = 16;

/// NeuQuant's sampling factor: 1 looks at every pixel, 30 at one in thirty. The palette
/// is learnt once, so a careful one is affordable.
const QUANT_SAMPLING: i32 = 3;

/// Writes an animated GIF of `count` frames of `size` pixels at `path`, atomically,
/// `delay_ms` apart, looping for ever. `draw(i, canvas)` draws frame i on a white
/// canvas; it is called from several threads at once.
///
/// # Errors
/// No frame, a drawing error, a picture too large for a GIF, or an unwritable file.
pub fn write_gif<F>(
    path: &Path,
    size: (u32, u32),
    delay_ms: u32,
    count: usize,
    draw: F,
) -> Result<()>
where
    F: Fn(usize, &Canvas<'_>) -> Result<()> + Sync,
{
    if count == 0 {
        return Err(FigureError::Data("no frame to animate"));
    }
    let (Ok(w), Ok(h)) = (u16::try_from(size.0), u16::try_from(size.1)) else {
        return Err(FigureError::Data(
            "an animation frame is too large for a GIF",
        ));
    };
    register_font();
    let render = |i: usize| render_frame(size, |c| draw(i, c));
    let first = render(0)?;
    let last = if count > 1 {
        render(count - 1)?
    } else {
        first.clone()
    };
    let palette = Palette::learn(&[&first, &last]);
    let tmp = file::temp_sibling(path);
    {
        let out = File::create(&tmp).map_err(|e| write_error(path, e))?;
        let mut encoder = gif::Encoder::new(BufWriter::new(out), w, h, &palette.rgb)
            .map_err(|e| write_error(path, e))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| write_error(path, e))?;
        let delay = u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX);
        let mut previous: Option<Vec<u8>> = None;
        for start in (0..count).step_by(BATCH) {
            let end = (start + BATCH).min(count);
            let indexed: Vec<Vec<u8>> = (start..end)
                .into_par_iter()
                .map(|i| match i {
                    0 => Ok(palette.index(&first)),
                    i if i == count - 1 => Ok(palette.index(&last)),
                    i => render(i).map(|rgb| palette.index(&rgb)),
                })
                .collect::<Result<_>>()?;
            for frame in indexed {
                let mut gif_frame = changed_part(previous.as_deref(), &frame, w, h);
                gif_frame.delay = delay;
                encoder
                    .write_frame(&gif_frame)
                    .map_err(|e| write_error(path, e))?;
                previous = Some(frame);
            }
        }
    }
    file::commit_temp(path).map_err(|e| write_error(path, e))
}

/// Draws one frame on a white canvas into an RGB buffer.
fn render_frame(size: (u32, u32), draw: impl FnOnce(&Canvas<'_>) -> Result<()>) -> Result<Vec<u8>> {
    let mut rgb = vec![255; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw(&root)?;
        root.present().map_err(err)?;
    }
    Ok(rgb)
}

/// The one palette of an animation.
struct Palette {
    quant: NeuQuant,
    /// The 256 colours, RGB, as the GIF's global colour table.
    rgb: Vec<u8>,
}

impl Palette {
    /// Learns 256 colours from the pixels of `frames` (RGB buffers).
    fn learn(frames: &[&Vec<u8>]) -> Self {
        let rgba: Vec<u8> = frames
            .iter()
            .flat_map(|f| f.chunks_exact(3))
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        let quant = NeuQuant::new(QUANT_SAMPLING, 256, &rgba);
        let rgb = quant.color_map_rgb();
        Self { quant, rgb }
    }

    /// The palette index of every pixel of an RGB buffer. A frame holds few distinct
    /// colours in long runs, so the last pixel and a cache spare most look-ups.
    fn index(&self, rgb: &[u8]) -> Vec<u8> {
        let mut cache: HashMap<[u8; 3], u8> = HashMap::new();
        let mut last: Option<([u8; 3], u8)> = None;
        rgb.chunks_exact(3)
            .map(|p| {
                let colour = [p[0], p[1], p[2]];
                if let Some((c, i)) = last.filter(|(c, _)| *c == colour) {
                    last = Some((c, i));
                    return i;
                }
                let i = *cache.entry(colour).or_insert_with(|| {
                    let k = self.quant.index_of(&[p[0], p[1], p[2], 255]);
                    u8::try_from(k).unwrap_or(u8::MAX)
                });
                last = Some((colour, i));
                i
            })
            .collect()
    }
}

/// The GIF frame that turns `previous` (palette indices, `w` × `h`) into `frame`: the
/// smallest rectangle holding every changed pixel, drawn over what is kept (one pixel
/// when nothing changed; a GIF frame cannot be empty). The whole frame when there is
/// no previous one.
fn changed_part(previous: Option<&[u8]>, frame: &[u8], w: u16, h: u16) -> gif::Frame<'static> {
    let (wi, hi) = (usize::from(w), usize::from(h));
    let (mut x0, mut x1, mut y0, mut y1) = (wi, 0, hi, 0);
    if let Some(prev) = previous {
        for y in 0..hi {
            let row = y * wi..(y + 1) * wi;
            let (a, b) = (&prev[row.clone()], &frame[row]);
            let Some(first) = a.iter().zip(b).position(|(p, q)| p != q) else {
                continue;
            };
            let last = wi
                - 1
                - a.iter()
                    .rev()
                    .zip(b.iter().rev())
                    .position(|(p, q)| p != q)
                    .unwrap_or(0);
            (x0, x1, y0, y1) = (x0.min(first), x1.max(last + 1), y0.min(y), y + 1);
        }
        if x0 >= x1 {
            (x0, x1, y0, y1) = (0, 1, 0, 1);
        }
    } else {
        (x0, x1, y0, y1) = (0, wi, 0, hi);
    }
    let buffer: Vec<u8> = (y0..y1)
        .flat_map(|y| frame[y * wi + x0..y * wi + x1].iter().copied())
        .collect();
    // The rectangle lies inside a w × h picture, so its sides fit in u16.
    let side = |v: usize| u16::try_from(v).unwrap_or(u16::MAX);
    gif::Frame {
        left: side(x0),
        top: side(y0),
        width: side(x1 - x0),
        height: side(y1 - y0),
        dispose: gif::DisposalMethod::Keep,
        buffer: Cow::Owned(buffer),
        ..gif::Frame::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square that moves one step right each frame, on white.
    fn moving_square(i: usize, c: &Canvas<'_>) -> Result<()> {
        let x = 10 + 8 * i32::try_from(i).unwrap_or(0);
        c.draw(&Rectangle::new(
            [(x, 20), (x + 20, 40)],
            RGBColor(0, 114, 178).filled(),
        ))
        .map_err(err)
    }

    fn decode(path: &Path) -> (Option<Vec<u8>>, Vec<gif::Frame<'static>>) {
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::Indexed);
        let mut d = options.read_info(File::open(path).unwrap()).unwrap();
        let global = d.global_palette().map(<[u8]>::to_vec);
        let mut frames = Vec::new();
        while let Some(f) = d.read_next_frame().unwrap() {
            frames.push(f.clone());
        }
        (global, frames)
    }

    #[test]
    fn one_palette_and_only_the_changed_rectangle_per_frame() {
        let dir = std::env::temp_dir().join(format!("figures-gif-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("square.gif");
        write_gif(&path, (120, 60), 80, 5, moving_square).unwrap();
        let (global, frames) = decode(&path);
        std::fs::remove_dir_all(&dir).ok();
        assert_eq!(frames.len(), 5);
        // One colour table for the animation, none per frame: one quantization, not five.
        assert_eq!(global.map(|p| p.len()), Some(256 * 3));
        assert!(frames.iter().all(|f| f.palette.is_none()));
        assert_eq!((frames[0].width, frames[0].height), (120, 60));
        for f in &frames[1..] {
            // The square moved 8 px: the old and the new square, 28 × 20 px (and the
            // anti-aliased edge), not the whole picture.
            assert!(f.width <= 30 && f.height <= 22, "{}x{}", f.width, f.height);
            assert_eq!(f.delay, 8);
        }
    }

    #[test]
    fn no_frame_is_refused() {
        let path = std::env::temp_dir().join("figures-gif-none.gif");
        let e = write_gif(&path, (10, 10), 80, 0, moving_square).unwrap_err();
        assert_eq!(e.to_string(), "no frame to animate");
    }
}
