//! The egui panel: what the last frame measured, and the controls. It only
//! reads [`Status`] and returns [`Action`]s; the app applies them, as it
//! applies the same actions from the keyboard.

use hroc::Method;
use hroc_bench::bench::Check;
use hroc_bench::render::pictures::Picture;

/// What the user asked for this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Switch to `Method::ALL[i]` (a new culler: its first frame is a frame 0).
    Method(usize),
    View(Picture),
    /// Play (back on the path, where it was left) or pause.
    Play(bool),
    /// Jump to a path time (leaves free flight).
    Seek(f32),
    /// Compare the next frame with `noc`.
    Check,
    Screenshot,
}

/// The views, with their keys.
pub const VIEWS: [(Picture, &str); 4] = [(Picture::Color, "colour"), (Picture::Overdraw, "overdraw"), (Picture::Id, "object ID"), (Picture::Groups, "tested boxes")];

/// Everything the panel shows.
pub struct Status {
    /// Scene, objects and triangles.
    pub scene: String,
    pub adapter: String,
    pub objects: usize,
    pub method: usize,
    pub view: Picture,
    pub playing: bool,
    /// The fly camera drives the view (the path is paused).
    pub free: bool,
    pub speed: f32,
    pub time: f32,
    /// First and last key time of the path.
    pub path: (f32, f32),
    pub fps: f64,
    pub wall_ms: f64,
    /// GPU ms per stage of the last frame.
    pub stages: Vec<(&'static str, f64)>,
    pub drawn: usize,
    /// The method that culled the last frame (`auto`'s choice).
    pub culled_by: &'static str,
    /// The method's statistics of the last frame (|V| |O| |G| |U| |D|...).
    pub stats: Vec<(&'static str, f64)>,
    /// Boxes the method tested (groups view); `None` for methods that test none.
    pub boxes: Option<usize>,
    /// The last check against `noc`, and where it was taken.
    pub check: Option<(String, Check)>,
    /// Last screenshot written, or why something failed.
    pub message: String,
}

pub fn panel(ctx: &egui::Context, s: &Status) -> Vec<Action> {
    let mut out = Vec::new();
    egui::Window::new("hroc view").default_pos([8.0, 8.0]).resizable(false).vscroll(true).show(ctx, |ui| {
        ui.label(&s.scene);
        ui.small(&s.adapter);
        ui.separator();

        let mut method = s.method;
        egui::ComboBox::from_label("method (M/N)").selected_text(Method::ALL[s.method].name()).show_ui(ui, |ui| {
            for (i, (name, _, what)) in Method::names().into_iter().enumerate() {
                ui.selectable_value(&mut method, i, name).on_hover_text(what);
            }
        });
        if method != s.method {
            out.push(Action::Method(method));
        }
        ui.horizontal(|ui| {
            for (k, (v, name)) in VIEWS.iter().enumerate() {
                if ui.radio(s.view == *v, *name).on_hover_text(format!("key {}", k + 1)).clicked() {
                    out.push(Action::View(*v));
                }
            }
        });
        if s.view == Picture::Groups && s.boxes.is_none() {
            ui.colored_label(egui::Color32::YELLOW, "this method tests no boxes");
        }

        ui.horizontal(|ui| {
            if ui.button(if s.playing { "pause" } else { "play" }).on_hover_text("Space").clicked() {
                out.push(Action::Play(!s.playing));
            }
            let mut t = s.time;
            if ui.add(egui::Slider::new(&mut t, s.path.0..=s.path.1.max(s.path.0)).suffix(" s")).changed() {
                out.push(Action::Seek(t));
            }
        });
        if s.free {
            ui.label(format!("free camera, {:.3} units/s (wheel)", s.speed));
        }
        ui.separator();

        ui.horizontal(|ui| {
            if ui.button("check against noc").on_hover_text("false negatives and missing pixels of the next frame").clicked() {
                out.push(Action::Check);
            }
            if ui.button("screenshot").on_hover_text("P or F12").clicked() {
                out.push(Action::Screenshot);
            }
        });
        if let Some((at, c)) = &s.check {
            let color = if c.false_negatives == 0 && c.missing_pixels == 0 { egui::Color32::LIGHT_GREEN } else { egui::Color32::LIGHT_RED };
            ui.colored_label(color, format!("{at}: {} false negatives, {} missing pixels", c.false_negatives, c.missing_pixels));
        }
        if !s.message.is_empty() {
            ui.label(&s.message);
        }
        ui.separator();

        ui.label(format!("{:.1} fps, frame {:.2} ms wall", s.fps, s.wall_ms));
        let n = s.objects.max(1) as f64;
        ui.label(format!("drawn {} of {}, C/N {:.3}", s.drawn, s.objects, (s.objects - s.drawn.min(s.objects)) as f64 / n));
        if Method::ALL[s.method] == Method::Auto {
            ui.label(format!("auto ran {}", s.culled_by));
        }
        if let Some(b) = s.boxes {
            ui.label(format!("tested boxes {b}"));
        }
        // Stages and the method's statistics side by side: the panel must fit a small window.
        ui.horizontal_top(|ui| {
            egui::Grid::new("stages").striped(true).num_columns(2).show(ui, |ui| {
                for (name, ms) in &s.stages {
                    ui.label(*name);
                    ui.monospace(format!("{ms:7.3} ms"));
                    ui.end_row();
                }
                ui.strong("GPU");
                ui.monospace(format!("{:7.3} ms", s.stages.iter().map(|st| st.1).sum::<f64>()));
                ui.end_row();
            });
            if !s.stats.is_empty() {
                ui.separator();
                egui::Grid::new("stats").striped(true).num_columns(2).show(ui, |ui| {
                    for (name, v) in &s.stats {
                        ui.label(*name);
                        ui.monospace(format!("{v:9.1}"));
                        ui.end_row();
                    }
                });
            }
        });
        ui.collapsing("keys", |ui| {
            ui.label("WASD move, E/Q up/down, right mouse look, wheel speed\nSpace play/pause, 1-4 views, M/N method\nP/F12 screenshot, Esc quit");
        });
    });
    out
}
