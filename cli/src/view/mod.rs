//! `tessgen view MESH`: the surface in a window (winit + wgpu), drawn every
//! frame by the runtime's renderers — [`SurfaceRenderer`] at a uniform
//! level, [`AdaptiveSurfaceRenderer`] with the buckets built on the GPU
//! from a metric that follows the camera — into an offscreen target of the
//! same formats as `render`, then put on the window with the HUD over it
//! (`hud.rs`). Keys change [`state::Settings`]; a scripted key sequence
//! (`--keys`), a frame count (`--frames`) and `--screenshot` make the same
//! window testable under Xvfb.

mod hud;
pub(crate) mod state;

use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use tessgen_runtime::adaptive::{Adaptive, Metric, Partitioning};
use tessgen_runtime::displace::{DisplaceMap, Displacement, Ownership};
use tessgen_runtime::gpu::renderer::{AdaptiveSurfaceRenderer, SurfaceOptions, SurfaceRenderer};
use tessgen_runtime::gpu::{Gpu, GpuMesh, Limits};
use tessgen_runtime::render::{Camera, Image, Readback, Target};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

use crate::gpu_cmds::{parse_camera, parse_size, surface_input, SurfaceInput};
use crate::CmdResult;
use state::{Action, Change, MetricKind, Orbit, Settings};

/// Look at a mesh's smooth surface in a window: orbit, switch schemes and levels, adaptive and displaced (keys: H in the window).
#[derive(clap::Args, Debug)]
pub(crate) struct ViewArgs {
    /// Input OBJ mesh, tags applied (non-quads and semi-sharp creases refined uniformly, holes left out).
    pub mesh: std::path::PathBuf,
    /// Patch scheme to start with (pccm, acc, gregory, gregory-osd, g1cc, regular); Tab switches.
    #[arg(long, default_value = "pccm", value_parser = crate::parse_scheme)]
    pub scheme: String,
    /// Tessellation level N of every base face to start with; + and - change it.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=state::MAX_VIEW_LEVEL as i64))]
    pub level: u32,
    /// Window size.
    #[arg(long, value_name = "WxH", default_value = "1024x768")]
    pub size: String,
    /// Camera direction as azimuth,elevation in degrees (as `render`).
    #[arg(
        long,
        value_name = "AZ,EL",
        default_value = "35,25",
        allow_hyphen_values = true
    )]
    pub camera: String,
    /// Start with the wireframe of the base faces.
    #[arg(long)]
    pub wireframe: bool,
    /// Displacement map (PNG, red channel) for D; default: procedural bumps. The mesh needs `vt` on every face corner.
    #[arg(long, value_name = "MAP.png")]
    pub displace: Option<std::path::PathBuf>,
    /// Start with the HUD (status, frame time, help) hidden.
    #[arg(long)]
    pub no_hud: bool,
    /// Scripted keys, comma-separated (`tab,w,+,a`; `comma` for ,): one applied per frame from the second frame on, as if pressed.
    #[arg(long, value_name = "KEYS", value_parser = state::parse_keys)]
    pub keys: Option<state::Keys>,
    /// Quit after this many frames.
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
    /// Write the last frame (with --frames) as a PNG, as the window shows it.
    #[arg(long, value_name = "IMG.png", requires = "frames")]
    pub screenshot: Option<std::path::PathBuf>,
}

/// The offscreen target's formats: `render`'s ([`Target`]), so a frame
/// without the HUD is `render`'s image.
const COLOR: wgpu::TextureFormat = tessgen_runtime::render::COLOR;
const DEPTH: wgpu::TextureFormat = tessgen_runtime::render::DEPTH;

/// Largest adaptive level (the instanced path's buckets are powers of two).
const MAX_ADAPTIVE_LEVEL: u32 = 64;

pub(crate) fn view(args: &ViewArgs) -> CmdResult {
    let keys = args.keys.clone().map_or(Vec::new(), |k| k.0);
    let (w, h) = parse_size(&args.size)?;
    let dir = parse_camera(&args.camera)?;
    // Bad input fails here, before a window opens.
    let input = surface_input("view", &args.mesh, &args.scheme, args.level, None)?;
    let all_regular = surface_input("view", &args.mesh, "regular", args.level, None).is_ok();
    let map = match &args.displace {
        Some(p) => DisplaceMap::from_png(p).map_err(|e| e.to_string())?,
        // Bumps: four periods across each texture direction.
        None => DisplaceMap::from_fn(256, 256, |u, v| {
            let t = std::f32::consts::TAU * 4.0;
            0.5 * (t * u).sin() * (t * v).sin()
        }),
    };
    let home = Orbit {
        az: dir.x.atan2(dir.z).to_degrees(),
        el: dir.y.clamp(-1.0, 1.0).asin().to_degrees(),
        zoom: 1.0,
    };
    let mut settings = Settings::new(&args.scheme, args.level, all_regular, home);
    settings.wireframe = args.wireframe;
    settings.hud = !args.no_hud;
    #[cfg(all(unix, not(target_os = "macos")))]
    if ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .all(|v| std::env::var_os(v).is_none_or(|s| s.is_empty()))
    {
        return Err("cannot open a window: neither DISPLAY nor WAYLAND_DISPLAY is set (without a display, run it under Xvfb: xvfb-run tessgen view …)".into());
    }
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    let mut app = App {
        args,
        size: (w, h),
        input,
        map,
        settings,
        keys: keys.into_iter(),
        view: None,
        error: None,
        frames: 0,
    };
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    match app.error {
        Some(e) => Err(e),
        None => {
            // Frame times: from one frame's start to the next (the first
            // frame, which builds the pipelines, not counted).
            let mut ms = app.view.map_or(Vec::new(), |v| v.times);
            ms.sort_by(f64::total_cmp);
            match ms.first() {
                Some(min) => eprintln!(
                    "tessgen: view: {} frames, frame time median {:.2} ms, min {min:.2} ms",
                    app.frames,
                    ms[ms.len() / 2]
                ),
                None => eprintln!("tessgen: view: {} frames", app.frames),
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// The winit application: the window and GPU state once resumed.
struct App<'a> {
    args: &'a ViewArgs,
    size: (u32, u32),
    input: SurfaceInput,
    map: DisplaceMap,
    settings: Settings,
    /// Scripted keys left, one applied per frame after the first.
    keys: std::vec::IntoIter<Action>,
    view: Option<View>,
    error: Option<String>,
    frames: u64,
}

/// One scheme's surface on the GPU and its renderers (the adaptive one
/// made the first time adaptive is switched on).
struct Surface {
    mesh: GpuMesh<'static>,
    /// The topology uploaded (the adaptive renderer's edge ids).
    topo: tessgen_runtime::Topology,
    uniform: SurfaceRenderer,
    adaptive: Option<AdaptiveSurfaceRenderer>,
    /// Level drawn per patch (a refined face runs at level / 2^steps).
    level: u32,
}

/// The window, its swapchain, the offscreen target and the surface.
struct View {
    window: Arc<Window>,
    gpu: &'static Gpu,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The non-sRGB view format the composite writes (the bytes as drawn).
    view_format: wgpu::TextureFormat,
    target: Target,
    composite: hud::Composite,
    /// The composite pipeline for RGBA8 screenshots.
    shot: hud::Composite,
    drawn: Surface,
    /// The mesh's file name, for the HUD.
    name: String,
    /// The mesh's bounding box: what the camera frames.
    bounds: (Vec3, Vec3),
    modifiers: ModifiersState,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    last: Instant,
    frame_ms: f64,
    /// Every frame's time after the first, for the summary at exit.
    times: Vec<f64>,
    hud_at: Option<Instant>,
    message: Option<String>,
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.view.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(v) => self.view = Some(v),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(view) = self.view.as_mut() else {
            return;
        };
        let mut actions = Vec::new();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(s) => {
                self.size = (s.width.max(1), s.height.max(1));
                view.resize(self.size);
            }
            WindowEvent::ModifiersChanged(m) => view.modifiers = m.state(),
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if let Some(a) = key_name(&event.logical_key, view.modifiers)
                    .as_deref()
                    .and_then(state::action_for)
                {
                    actions.push(a);
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => view.drag = (state == ElementState::Pressed).then_some(view.cursor),
            WindowEvent::CursorMoved { position, .. } => {
                view.cursor = (position.x, position.y);
                if let Some((x, y)) = view.drag {
                    let (dx, dy) = (position.x - x, position.y - y);
                    actions.push(Action::Orbit(-0.3 * dx as f32, 0.3 * dy as f32));
                    view.drag = Some(view.cursor);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                actions.push(Action::Zoom(0.9f32.powf(lines)));
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame() {
                    self.error = Some(e);
                    event_loop.exit();
                    return;
                }
                if self.args.frames.is_some_and(|n| self.frames >= n) {
                    event_loop.exit();
                }
            }
            _ => {}
        }
        for a in actions {
            if let Err(e) = self.act(a) {
                self.error = Some(e);
            }
            if a == Action::Quit || self.error.is_some() {
                event_loop.exit();
            }
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(v) = &self.view {
            v.window.request_redraw();
        }
    }
}

/// The `--keys` name of a pressed key (`tab`, `shift+tab`, `a`, `left`, …).
fn key_name(key: &Key, modifiers: ModifiersState) -> Option<String> {
    let name = match key {
        Key::Named(n) => match n {
            NamedKey::Tab if modifiers.shift_key() => "shift+tab",
            NamedKey::Tab => "tab",
            NamedKey::ArrowLeft => "left",
            NamedKey::ArrowRight => "right",
            NamedKey::ArrowUp => "up",
            NamedKey::ArrowDown => "down",
            NamedKey::PageUp => "pageup",
            NamedKey::PageDown => "pagedown",
            NamedKey::Escape => "escape",
            NamedKey::F1 => "f1",
            _ => return None,
        }
        .to_string(),
        Key::Character(c) => c.to_lowercase(),
        _ => return None,
    };
    Some(name)
}

impl App<'_> {
    /// The window, a device that can present to it, the first surface.
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<View, String> {
        let (w, h) = self.size;
        let window = Arc::new(
            event_loop
                .create_window(
                    Window::default_attributes()
                        .with_title(format!("tessgen view: {}", self.args.mesh.display()))
                        .with_inner_size(winit::dpi::PhysicalSize::new(w, h))
                        .with_resizable(true),
                )
                .map_err(|e| format!("cannot open a window: {e}"))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| format!("cannot draw into the window: {e}"))?;
        let (gpu, adapter) = pollster::block_on(open_gpu(&instance, &surface))?;
        // The program's device for the rest of its life.
        let gpu: &'static Gpu = Box::leak(Box::new(gpu));
        let caps = surface.get_capabilities(&adapter);
        let format = *caps
            .formats
            .iter()
            .find(|f| !f.is_srgb())
            .or(caps.formats.first())
            .ok_or_else(|| format!("{} cannot present to this window", gpu.info.name))?;
        let view_format = format.remove_srgb_suffix();
        let size = window.inner_size();
        self.size = (size.width.max(1), size.height.max(1));
        let mut config = surface
            .get_default_config(&adapter, self.size.0, self.size.1)
            .ok_or_else(|| format!("{} cannot present to this window", gpu.info.name))?;
        config.format = format;
        config.view_formats = vec![view_format];
        surface.configure(&gpu.device, &config);
        let drawn = self.surface_for(gpu)?;
        Ok(View {
            target: target(gpu, self.size),
            composite: hud::Composite::new(&gpu.device, view_format),
            shot: hud::Composite::new(&gpu.device, COLOR),
            window,
            gpu,
            surface,
            config,
            view_format,
            drawn,
            bounds: bounds(&self.input.positions),
            name: self
                .args
                .mesh
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
            modifiers: ModifiersState::empty(),
            drag: None,
            cursor: (0.0, 0.0),
            last: Instant::now(),
            frame_ms: 0.0,
            times: Vec::new(),
            hud_at: None,
            message: None,
        })
    }

    /// The current scheme's surface, displaced if asked.
    fn surface_for(&self, gpu: &'static Gpu) -> Result<Surface, String> {
        let s = &self.settings;
        let input = if s.scheme() == self.args.scheme {
            None
        } else {
            Some(surface_input(
                "view",
                &self.args.mesh,
                s.scheme(),
                s.level,
                None,
            )?)
        };
        let input = input.as_ref().unwrap_or(&self.input);
        let at = |e: tessgen_runtime::gpu::GpuError| format!("{}: {e}", self.args.mesh.display());
        let mesh = if s.displace {
            let (lo, hi) = bounds(&input.positions);
            let d = Displacement {
                map: self.map.clone(),
                scale: s.displace_scale * (hi - lo).length(),
                ownership: Ownership::LowestFace,
            };
            GpuMesh::new_displaced(
                gpu,
                &input.mesh,
                &input.topo,
                &input.positions,
                s.scheme(),
                &d,
            )
            .map_err(at)?
        } else {
            GpuMesh::new(gpu, &input.topo, &input.positions, s.scheme()).map_err(at)?
        };
        let level = input.leaf_level(s.level);
        let uniform = SurfaceRenderer::new(&mesh, &self.options(level)).map_err(at)?;
        Ok(Surface {
            mesh,
            topo: input.topo.clone(),
            uniform,
            adaptive: None,
            level,
        })
    }

    fn options(&self, level: u32) -> SurfaceOptions {
        SurfaceOptions {
            color: COLOR,
            depth: Some(DEPTH),
            samples: 1,
            level,
            wireframe: self.settings.wireframe,
            plain: !self.settings.class_colours,
        }
    }

    /// Apply a key's action: the settings, then what they need redone.
    fn act(&mut self, a: Action) -> Result<(), String> {
        let change = self.settings.apply(a);
        let level = self.input.leaf_level(self.settings.level);
        let opts = self.options(level);
        let shot = format!("tessgen-view-{}.png", self.frames);
        let upload = match change {
            Change::Upload => Some(
                self.view
                    .as_ref()
                    .map(|v| v.gpu)
                    .map(|g| self.surface_for(g)),
            ),
            _ => None,
        };
        let Some(view) = self.view.as_mut() else {
            return Ok(());
        };
        view.hud_at = None;
        match change {
            Change::Frame | Change::Quit => {}
            Change::Screenshot => {
                if let Some(img) = view.draw(&self.settings, self.size, true)? {
                    img.save_png(&shot).map_err(|e| e.to_string())?;
                    view.message = Some(format!("saved {shot}"));
                }
            }
            Change::Draw => {
                let s = &mut view.drawn;
                s.level = level;
                s.uniform.set_level(&s.mesh, level);
                s.uniform.set_wireframe(opts.wireframe);
                s.uniform.set_plain(opts.plain);
                if let Some(a) = &mut s.adaptive {
                    a.set_wireframe(opts.wireframe);
                    a.set_plain(opts.plain);
                }
            }
            Change::Upload => match upload.flatten() {
                Some(Ok(s)) => {
                    view.drawn = s;
                    view.message = None;
                }
                // A mesh without texture coordinates, a scheme this mesh
                // cannot take: said on screen, the view stays as it was.
                Some(Err(e)) => {
                    if matches!(a, Action::NextScheme | Action::PrevScheme) {
                        let back = if a == Action::NextScheme {
                            Action::PrevScheme
                        } else {
                            Action::NextScheme
                        };
                        self.settings.apply(back);
                    } else {
                        self.settings.displace = false;
                    }
                    eprintln!("tessgen: view: {e}");
                    view.message = Some(e);
                }
                None => {}
            },
        }
        Ok(())
    }

    /// One frame: the scripted key of this frame, the surface, the HUD,
    /// present; the screenshot after the last scripted frame.
    fn frame(&mut self) -> Result<(), String> {
        if self.frames > 0 {
            if let Some(a) = self.keys.next() {
                self.act(a)?;
            }
        }
        self.frames += 1;
        let last = self.args.frames.is_some_and(|n| self.frames >= n);
        let shoot = last && self.args.screenshot.is_some();
        let view = self.view.as_mut().ok_or("no window")?;
        let img = view.draw(&self.settings, self.size, shoot)?;
        if let (Some(img), Some(path)) = (img, &self.args.screenshot) {
            img.save_png(path).map_err(|e| e.to_string())?;
            eprintln!("tessgen: view: screenshot {}", path.display());
        }
        Ok(())
    }
}

impl View {
    fn resize(&mut self, (w, h): (u32, u32)) {
        self.config.width = w;
        self.config.height = h;
        self.surface.configure(&self.gpu.device, &self.config);
        self.target = target(self.gpu, (w, h));
    }

    /// The camera of the orbit: `render`'s framing, moved by the zoom.
    fn camera(&self, s: &Settings) -> Camera {
        let (lo, hi) = self.bounds;
        let (az, el) = (s.orbit.az.to_radians(), s.orbit.el.to_radians());
        let dir = Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
        let mut c = Camera::framing(lo, hi, dir);
        c.eye = c.target + (c.eye - c.target) * s.orbit.zoom;
        c
    }

    /// Draw and present one frame; with `shoot`, also composite it into an
    /// RGBA8 texture and return it read back.
    fn draw(
        &mut self,
        s: &Settings,
        (w, h): (u32, u32),
        shoot: bool,
    ) -> Result<Option<Image>, String> {
        let gpu = self.gpu;
        let now = Instant::now();
        let ms = now.duration_since(self.last).as_secs_f64() * 1e3;
        self.last = now;
        // The first frame's time is the window's opening: not counted.
        if self.frame_ms == 0.0 {
            self.frame_ms = f64::MIN_POSITIVE;
        } else {
            self.times.push(ms);
            self.frame_ms = if self.times.len() == 1 {
                ms
            } else {
                0.9 * self.frame_ms + 0.1 * ms
            };
        }
        let camera = self.camera(s);
        let view_proj = camera.view_proj(w as f32 / h as f32);
        let surface = &mut self.drawn;
        let err = |e: tessgen_runtime::gpu::GpuError| e.to_string();
        if s.adaptive {
            let a = Adaptive {
                metric: match s.metric {
                    MetricKind::Screen(px) => Metric::Screen {
                        view_proj,
                        viewport: [w as f32, h as f32],
                        pixels_per_segment: px,
                    },
                    MetricKind::Distance(k) => Metric::Distance {
                        eye: camera.eye,
                        scale: k,
                    },
                },
                partitioning: Partitioning::Integer,
                min: 1.0,
                max: MAX_ADAPTIVE_LEVEL as f32,
            };
            if surface.adaptive.is_none() {
                let opts = surface.uniform.options();
                let r = AdaptiveSurfaceRenderer::new(
                    &surface.mesh,
                    &surface.topo,
                    &a,
                    MAX_ADAPTIVE_LEVEL,
                    opts,
                )
                .map_err(err)?;
                surface.adaptive = Some(r);
            }
            let r = surface.adaptive.as_ref().ok_or("no adaptive renderer")?;
            r.set_adaptive(&surface.mesh, &a).map_err(err)?;
            r.prepare(&surface.mesh, view_proj);
        } else {
            surface.uniform.prepare(&surface.mesh, view_proj);
        }
        // The HUD: rewritten a few times a second (frame time) or at once
        // after a key.
        if self
            .hud_at
            .is_none_or(|t| now.duration_since(t).as_millis() > 250)
        {
            let text = if s.hud {
                let samples =
                    (!s.adaptive).then(|| surface.uniform.samples_per_frame(&surface.mesh));
                let mut lines = vec![format!("tessgen view  {}  on {}", self.name, gpu.info.name)];
                lines.extend(s.status(surface.level, samples, self.frame_ms));
                if let Some(m) = &self.message {
                    lines.push(m.clone());
                }
                if s.help {
                    lines.push(String::new());
                    lines.extend(Settings::help_lines());
                }
                hud::TextBox::new(&lines, if w >= 1000 { 2 } else { 1 })
            } else {
                hud::TextBox::empty()
            };
            self.composite.set_text(&gpu.device, &gpu.queue, &text);
            self.shot.set_text(&gpu.device, &gpu.queue, &text);
            self.hud_at = Some(now);
        }
        use wgpu::CurrentSurfaceTexture as Current;
        let frame = match self.surface.get_current_texture() {
            Current::Success(t) | Current::Suboptimal(t) => t,
            // Nothing to draw into this time (minimised, resized): the
            // next frame tries again.
            Current::Timeout | Current::Occluded => return Ok(None),
            Current::Outdated | Current::Lost => {
                self.surface.configure(&gpu.device, &self.config);
                return Ok(None);
            }
            other => return Err(format!("window surface: {other:?}")),
        };
        let out = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let frame_view = self.target.color.create_view(&Default::default());
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view"),
            });
        let surface = &self.drawn;
        if let (true, Some(r)) = (s.adaptive, &surface.adaptive) {
            r.encode(&surface.mesh, &mut enc).map_err(err)?;
        }
        {
            let mut pass = self.target.pass(&mut enc, wgpu::Color::WHITE);
            match (s.adaptive, &surface.adaptive) {
                (true, Some(r)) => r.draw(&mut pass),
                _ => surface.uniform.draw(&mut pass),
            }
        }
        self.composite
            .encode(&gpu.device, &mut enc, &frame_view, &out);
        // A screenshot: the same composite into an RGBA8 texture, read back.
        let shot = shoot.then(|| {
            let tex = Target::new(gpu, w, h, wgpu::TextureUsages::COPY_SRC).color;
            self.shot.encode(
                &gpu.device,
                &mut enc,
                &frame_view,
                &tex.create_view(&Default::default()),
            );
            Readback::copy(gpu, &mut enc, &tex)
        });
        gpu.queue.submit([enc.finish()]);
        self.window.pre_present_notify();
        gpu.queue.present(frame);
        match shot {
            Some(r) => r.image(&surface.mesh).map(Some).map_err(err),
            None => Ok(None),
        }
    }
}

/// The offscreen target of a window size (sampled by the composite).
fn target(gpu: &Gpu, (w, h): (u32, u32)) -> Target {
    Target::new(gpu, w, h, wgpu::TextureUsages::TEXTURE_BINDING)
}

/// Bounding box of `positions`.
pub(crate) fn bounds(positions: &[Vec3]) -> (Vec3, Vec3) {
    positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// A device on an adapter that can present to `surface` (as `Gpu::new`
/// asks for one: the adapter's own limits, no extra features).
async fn open_gpu(
    instance: &wgpu::Instance,
    surface: &wgpu::Surface<'_>,
) -> Result<(Gpu, wgpu::Adapter), String> {
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            compatible_surface: Some(surface),
            ..Default::default()
        })
        .await
        .map_err(|e| format!("no GPU adapter can draw into the window: {e}"))?;
    let info = adapter.get_info();
    let al = adapter.limits();
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("tessgen view"),
            required_limits: al.clone(),
            ..Default::default()
        })
        .await
        .map_err(|e| format!("{}: {e}", info.name))?;
    let limits = Limits {
        max_workgroups_per_dimension: al.max_compute_workgroups_per_dimension,
        max_texture_dimension_2d: al.max_texture_dimension_2d,
        max_storage_buffer_binding_size: al.max_storage_buffer_binding_size as u64,
    };
    Ok((Gpu::from_parts(device, queue, info, limits), adapter))
}
