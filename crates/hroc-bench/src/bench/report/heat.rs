//! Overdraw heat maps of `roc`, `hroc` and `ref` at one frame, side by side,
//! and their differences (Lee et al. 2021 Figure 7; Lee's thesis, Figure 17).

use serde::Serialize;
use std::path::Path;

use crate::bench::Session;
use crate::bvh::Split;
use crate::error::Result;
use crate::gpu::Headless;
use crate::render::pictures;
use crate::scene::Scene;
use hroc::Method;

/// The methods compared: per-object box tests, HROC, and the ideal.
const METHODS: [Method; 3] = [Method::Roc, Method::HROC, Method::Ref];
/// Differences shown: what HROC draws beyond the ideal, and what it saves over ROC.
const DIFFS: [(Method, Method); 2] = [(Method::HROC, Method::Ref), (Method::Roc, Method::HROC)];

#[derive(Clone, Debug, Serialize)]
pub struct HeatMap {
    pub name: String,
    /// PNG path relative to the report folder.
    pub file: String,
    /// Mean fragments per pixel (for a difference: mean difference).
    pub mean: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct HeatMaps {
    pub frame: usize,
    pub maps: Vec<HeatMap>,
    pub diffs: Vec<HeatMap>,
}

/// Runs each method from frame 0 to `frame` (they depend on the previous
/// frame's visibility) and saves its overdraw at `frame` into `dir`.
pub fn render(gpu: &Headless, scene: &Scene, frames: usize, res: (u32, u32), frame: usize, dir: &Path) -> Result<HeatMaps> {
    let mut s = Session::new(gpu, scene.clone(), None, frames, res, Split::Sah)?;
    let mut counts = Vec::new();
    let mut maps = Vec::new();
    for m in METHODS {
        let mut c = s.create(m)?;
        let mut lists = Vec::new();
        for k in 0..=frame {
            if c.wants_oracle() {
                let (_, truth) = s.truth(k)?;
                c.set_oracle(&s.culler, &truth.visible)?;
            }
            lists = s.run_frame(&mut c, k)?.lists;
        }
        let od = s.renderer.overdraw(gpu, &lists)?;
        let file = format!("images/overdraw-{m}.png");
        pictures::save_png(&dir.join(format!("overdraw-{m}.png")), res.0, res.1, &od.iter().map(|&v| pictures::heat(v)).collect::<Vec<_>>())?;
        maps.push(HeatMap { name: m.to_string(), file, mean: mean(&od) });
        counts.push(od);
    }
    let at = |method: Method| METHODS.iter().position(|&m| m == method).map(|i| &counts[i]);
    let mut diffs = Vec::new();
    for (a, b) in DIFFS {
        let (Some(x), Some(y)) = (at(a), at(b)) else { continue };
        let d: Vec<f32> = x.iter().zip(y).map(|(p, q)| p - q).collect();
        let stem = format!("overdraw-{a}-minus-{b}");
        pictures::save_png(&dir.join(format!("{stem}.png")), res.0, res.1, &d.iter().map(|&v| diverging(v)).collect::<Vec<_>>())?;
        diffs.push(HeatMap { name: format!("{a} − {b}"), file: format!("images/{stem}.png"), mean: mean(&d) });
    }
    Ok(HeatMaps { frame, maps, diffs })
}

fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len().max(1) as f64
}

/// White at 0, toward red for more fragments, toward blue for fewer; ±4 saturates.
fn diverging(v: f32) -> [u8; 4] {
    let t = (v.abs() / 4.0).clamp(0.0, 1.0);
    let fade = (255.0 * (1.0 - t)) as u8;
    if v >= 0.0 {
        [255, fade, fade, 255]
    } else {
        [fade, fade, 255, 255]
    }
}

#[cfg(test)]
mod tests {
    use super::diverging;

    #[test]
    fn diverging_is_white_at_zero_and_saturates() {
        assert_eq!(diverging(0.0), [255, 255, 255, 255]);
        assert_eq!(diverging(4.0), [255, 0, 0, 255]);
        assert_eq!(diverging(100.0), [255, 0, 0, 255]);
        assert_eq!(diverging(-8.0), [0, 0, 255, 255]);
    }
}
