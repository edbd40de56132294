//! Renders the demo (a generated city, a wall, two blended panels) with the
//! forward host, culled by hroc, headless to PNG.
//!
//! `cargo run --release -p hroc-forward-host --example forward_host -- [METHOD] [OUT.png] [--backend vulkan|gl] [--tier full|portable] [--shadow-method M]`
//!
//! `--tier portable` runs hroc with an emulated draw count and ID marks
//! ([`hroc::device::Capabilities::PORTABLE`], what DX12 and Metal need), and the
//! host's opaque fragment shader then has no hroc line.
//!
//! The frame is an engine's ([`Views::ENGINE`]): a 4× MSAA main view and a
//! directional light's shadow map of three cascades, each culled as a view
//! of its own. On GL, whose wgpu backend cannot sample multisampled
//! textures or a layer other than 0 of an array, one single-sample view.
//! `--shadow-method` culls the cascades with another method (`hzb` by
//! default; `hroc-na` marks in the shadow pass's fragment stage). Each
//! frame's wall time (record, submit, wait) is printed, and its mean.

use hroc::device::Capabilities;
use hroc::{DepthRange, Method};
use hroc_forward_host::{open_device_on, Demo, ForwardHost, Views};

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let (mut positional, mut backends, mut capabilities, mut shadow_method) = (Vec::new(), wgpu::Backends::all(), None, Views::ENGINE.shadow_method);
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--backend" => {
                backends = match args.next().as_deref() {
                    Some("vulkan") => wgpu::Backends::VULKAN,
                    Some("gl") => wgpu::Backends::GL,
                    other => return Err(format!("--backend takes vulkan or gl, not {other:?}")),
                }
            }
            "--tier" => {
                capabilities = match args.next().as_deref() {
                    Some("full") => None,
                    Some("portable") => Some(Capabilities::PORTABLE),
                    other => return Err(format!("--tier takes full or portable, not {other:?}")),
                }
            }
            "--shadow-method" => shadow_method = args.next().unwrap_or_default().parse().map_err(|e: hroc::Error| e.to_string())?,
            _ => positional.push(arg),
        }
    }
    let mut positional = positional.into_iter();
    let method: Method = positional.next().as_deref().unwrap_or("hroc").parse().map_err(|e: hroc::Error| e.to_string())?;
    let out = positional.next().unwrap_or_else(|| "forward_host.png".into());
    let (device, queue) = open_device_on(backends)?;
    let demo = Demo::new(3000, 16)?;
    let size = (640, 360);
    let views = if device.adapter_info().backend == wgpu::Backend::Gl { Views::SINGLE } else { Views { shadow_method, ..Views::ENGINE } };
    let mut host = ForwardHost::with_views(&device, &queue, &demo.scene, size, (method, DepthRange::Reversed, capabilities), views).map_err(|e| e.to_string())?;
    // The picture: the last frame before the cut (the wall, the blended panel
    // in front of it; the one behind it culled).
    let mut shown = None;
    let mut times = Vec::new();
    for k in 0..demo.cameras.len() {
        let (view, proj) = demo.matrices(k, size.0 as f32 / size.1 as f32, DepthRange::Reversed);
        let start = std::time::Instant::now();
        host.frame(view, proj, k == demo.cut).map_err(|e| e.to_string())?;
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| e.to_string())?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
        let f = host.output().map_err(|e| e.to_string())?;
        let drawn = f.drawn.iter().filter(|&&d| d).count();
        let cascades: Vec<String> = f.cascade_drawn.iter().map(|c| c.iter().filter(|&&d| d).count().to_string()).collect();
        let shadows = if cascades.is_empty() { String::new() } else { format!("; the cascades ({}) {}", views.shadow_method, cascades.join(", ")) };
        println!("frame {k:2}: {:.1} ms, {method} drew {drawn} of {} objects{shadows}", times[k], f.drawn.len());
        if k + 1 == demo.cut {
            shown = Some(f);
        }
    }
    // The first two frames build pipelines and the first occlusion maps.
    let warm = &times[2.min(times.len())..];
    println!("mean frame: {:.1} ms over frames 2 to {}", warm.iter().sum::<f64>() / warm.len().max(1) as f64, times.len().saturating_sub(1));
    let f = shown.ok_or("no frames")?;
    image::RgbaImage::from_raw(size.0, size.1, f.color).ok_or("image size")?.save(&out).map_err(|e| format!("{out}: {e}"))?;
    println!("wrote {out}");
    Ok(())
}
