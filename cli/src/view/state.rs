//! What the viewer shows, and what each key does to it: plain data and
//! one `apply`, so the window's key events and a scripted key sequence
//! (`--keys`, the tests) go through the same code.

/// The quad schemes `view` cycles through, in this order (`regular` only
/// where every face is regular: see [`Settings::new`]).
pub(crate) const SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd", "g1cc", "regular"];

/// The adaptive metric the viewer computes per frame from its camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MetricKind {
    /// Projected edge length over this many pixels per segment.
    Screen(f32),
    /// `K · |edge| / distance to the eye`.
    Distance(f32),
}

impl MetricKind {
    fn name(&self) -> String {
        match self {
            MetricKind::Screen(px) => format!("screen:{px}"),
            MetricKind::Distance(k) => format!("distance:{k}"),
        }
    }
}

/// Orbit camera around the mesh's bounding-box centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Orbit {
    /// Azimuth and elevation in degrees (as `render --camera AZ,EL`).
    pub az: f32,
    pub el: f32,
    /// Distance as a factor of the framing distance (1: as `render`).
    pub zoom: f32,
}

/// Everything the viewer's state holds that a key changes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Settings {
    /// Index into `schemes`.
    pub scheme: usize,
    /// The schemes this mesh can take.
    pub schemes: Vec<&'static str>,
    /// Uniform level of a base face.
    pub level: u32,
    pub adaptive: bool,
    pub metric: MetricKind,
    pub wireframe: bool,
    /// Class colours (ordinary orange, extraordinary blue) or one grey.
    pub class_colours: bool,
    pub displace: bool,
    /// Displacement scale in units of the bounding box's diagonal.
    pub displace_scale: f32,
    pub hud: bool,
    pub help: bool,
    pub orbit: Orbit,
    /// The orbit the camera resets to.
    pub home: Orbit,
}

/// What a key asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Action {
    NextScheme,
    PrevScheme,
    LevelUp,
    LevelDown,
    ToggleAdaptive,
    NextMetric,
    MetricFiner,
    MetricCoarser,
    ToggleWireframe,
    ToggleClassColours,
    ToggleDisplace,
    DisplaceMore,
    DisplaceLess,
    ToggleHud,
    ToggleHelp,
    /// Degrees of azimuth and elevation.
    Orbit(f32, f32),
    /// Factor on the distance.
    Zoom(f32),
    ResetCamera,
    Screenshot,
    Quit,
}

/// What the frame loop has to redo after an [`Action`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Change {
    /// Nothing (or only what every frame reads anyway: camera, metric,
    /// HUD).
    Frame,
    /// Draw options (level, wireframe, colours, adaptive on/off).
    Draw,
    /// The surface on the GPU (scheme, displacement).
    Upload,
    Screenshot,
    Quit,
}

/// The largest uniform level `view` offers (the GPU draws (N+1)² samples
/// per face every frame).
pub(crate) const MAX_VIEW_LEVEL: u32 = 64;

/// The key names `--keys` takes and the window's keys map to, with their
/// actions; the on-screen help is made from the same table.
pub(crate) const KEYS: &[(&str, Action, &str)] = &[
    ("tab", Action::NextScheme, "next scheme"),
    ("shift+tab", Action::PrevScheme, "previous scheme"),
    ("+", Action::LevelUp, "level up"),
    ("=", Action::LevelUp, ""),
    ("-", Action::LevelDown, "level down"),
    ("a", Action::ToggleAdaptive, "adaptive on/off"),
    ("m", Action::NextMetric, "metric screen/distance"),
    ("]", Action::MetricFiner, "metric finer"),
    ("[", Action::MetricCoarser, "metric coarser"),
    ("w", Action::ToggleWireframe, "wireframe"),
    ("c", Action::ToggleClassColours, "class colours"),
    ("d", Action::ToggleDisplace, "displacement on/off"),
    (".", Action::DisplaceMore, "displacement up"),
    (",", Action::DisplaceLess, "displacement down"),
    ("left", Action::Orbit(-10.0, 0.0), "orbit (or drag)"),
    ("right", Action::Orbit(10.0, 0.0), ""),
    ("up", Action::Orbit(0.0, 10.0), ""),
    ("down", Action::Orbit(0.0, -10.0), ""),
    ("pageup", Action::Zoom(1.0 / 1.2), "zoom (or wheel)"),
    ("pagedown", Action::Zoom(1.2), ""),
    ("r", Action::ResetCamera, "reset camera"),
    ("p", Action::Screenshot, "screenshot"),
    ("h", Action::ToggleHelp, "help"),
    ("f1", Action::ToggleHelp, ""),
    ("u", Action::ToggleHud, "HUD on/off"),
    ("escape", Action::Quit, "quit"),
    ("q", Action::Quit, ""),
];

/// The action of a key name (`tab`, `shift+tab`, `a`, `+`, `left`, …),
/// case-insensitive for letters.
pub(crate) fn action_for(key: &str) -> Option<Action> {
    let key = key.to_ascii_lowercase();
    KEYS.iter().find(|(k, _, _)| *k == key).map(|(_, a, _)| *a)
}

/// A scripted key sequence (`--keys`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Keys(pub Vec<Action>);

/// `--keys`: comma-separated key names (`,` itself is `comma`), each known.
pub(crate) fn parse_keys(s: &str) -> Result<Keys, String> {
    s.split(',')
        .filter(|k| !k.trim().is_empty())
        .map(|k| {
            let k = match k.trim() {
                "comma" => ",",
                other => other,
            };
            action_for(k).ok_or_else(|| {
                format!(
                    "unknown key `{k}` (known: {})",
                    KEYS.iter()
                        .map(|(k, _, _)| if *k == "," { "comma" } else { k })
                        .collect::<Vec<_>>()
                        .join(" ")
                )
            })
        })
        .collect::<Result<_, _>>()
        .map(Keys)
}

impl Settings {
    /// The start: `scheme` among the quad schemes the mesh can take
    /// (`regular` only if `all_regular`).
    pub fn new(scheme: &str, level: u32, all_regular: bool, home: Orbit) -> Settings {
        let schemes: Vec<&'static str> = SCHEMES
            .iter()
            .copied()
            .filter(|s| *s != "regular" || all_regular)
            .collect();
        Settings {
            scheme: schemes.iter().position(|s| *s == scheme).unwrap_or(0),
            schemes,
            level: level.clamp(1, MAX_VIEW_LEVEL),
            adaptive: false,
            metric: MetricKind::Screen(8.0),
            wireframe: false,
            class_colours: true,
            displace: false,
            displace_scale: 0.02,
            hud: true,
            help: false,
            orbit: home,
            home,
        }
    }

    pub fn scheme(&self) -> &'static str {
        self.schemes[self.scheme]
    }

    /// Apply one action; what the frame loop has to redo.
    pub fn apply(&mut self, a: Action) -> Change {
        let n = self.schemes.len();
        match a {
            Action::NextScheme => {
                self.scheme = (self.scheme + 1) % n;
                Change::Upload
            }
            Action::PrevScheme => {
                self.scheme = (self.scheme + n - 1) % n;
                Change::Upload
            }
            Action::LevelUp => {
                self.level = (self.level + 1).min(MAX_VIEW_LEVEL);
                Change::Draw
            }
            Action::LevelDown => {
                self.level = self.level.saturating_sub(1).max(1);
                Change::Draw
            }
            Action::ToggleAdaptive => {
                self.adaptive = !self.adaptive;
                Change::Draw
            }
            Action::NextMetric => {
                self.metric = match self.metric {
                    MetricKind::Screen(_) => MetricKind::Distance(8.0),
                    MetricKind::Distance(_) => MetricKind::Screen(8.0),
                };
                Change::Frame
            }
            Action::MetricFiner | Action::MetricCoarser => {
                let finer = a == Action::MetricFiner;
                self.metric = match self.metric {
                    // Fewer pixels per segment: more segments.
                    MetricKind::Screen(px) => MetricKind::Screen(
                        if finer { px / 2.0 } else { px * 2.0 }.clamp(0.5, 256.0),
                    ),
                    MetricKind::Distance(k) => MetricKind::Distance(
                        if finer { k * 2.0 } else { k / 2.0 }.clamp(0.125, 1024.0),
                    ),
                };
                Change::Frame
            }
            Action::ToggleWireframe => {
                self.wireframe = !self.wireframe;
                Change::Draw
            }
            Action::ToggleClassColours => {
                self.class_colours = !self.class_colours;
                Change::Draw
            }
            Action::ToggleDisplace => {
                self.displace = !self.displace;
                Change::Upload
            }
            Action::DisplaceMore | Action::DisplaceLess => {
                let f = if a == Action::DisplaceMore {
                    1.5
                } else {
                    1.0 / 1.5
                };
                self.displace_scale = (self.displace_scale * f).clamp(1e-4, 1.0);
                if self.displace {
                    Change::Upload
                } else {
                    Change::Frame
                }
            }
            Action::ToggleHud => {
                self.hud = !self.hud;
                Change::Frame
            }
            Action::ToggleHelp => {
                self.help = !self.help;
                self.hud |= self.help;
                Change::Frame
            }
            Action::Orbit(daz, del) => {
                self.orbit.az = (self.orbit.az + daz).rem_euclid(360.0);
                self.orbit.el = (self.orbit.el + del).clamp(-89.0, 89.0);
                Change::Frame
            }
            Action::Zoom(f) => {
                self.orbit.zoom = (self.orbit.zoom * f).clamp(0.05, 20.0);
                Change::Frame
            }
            Action::ResetCamera => {
                self.orbit = self.home;
                Change::Frame
            }
            Action::Screenshot => Change::Screenshot,
            Action::Quit => Change::Quit,
        }
    }

    /// The HUD's status lines.
    pub fn status(&self, level_drawn: u32, samples: Option<u64>, frame_ms: f64) -> Vec<String> {
        let mode = if self.adaptive {
            format!("adaptive {} (GPU-driven buckets)", self.metric.name())
        } else if level_drawn != self.level {
            format!("level {} ({} per refined face)", self.level, level_drawn)
        } else {
            format!("level {}", self.level)
        };
        let samples = samples.map_or("-".to_string(), group_thousands);
        let fps = if frame_ms > 0.0 {
            1000.0 / frame_ms
        } else {
            0.0
        };
        vec![
            format!(
                "{}  {}  {}{}{}",
                self.scheme(),
                mode,
                if self.wireframe { "wireframe  " } else { "" },
                if self.class_colours { "" } else { "plain  " },
                if self.displace {
                    format!("displaced x{:.4}", self.displace_scale)
                } else {
                    String::new()
                }
            ),
            format!("samples/frame {samples}  frame {frame_ms:.1} ms ({fps:.0} fps)   H: help"),
        ]
    }

    /// The help lines (from [`KEYS`]: each action's first key names it).
    pub fn help_lines() -> Vec<String> {
        let mut lines = Vec::new();
        let mut i = 0;
        while i < KEYS.len() {
            let what = KEYS[i].2;
            // Following rows with an empty description belong to this one.
            let mut j = i + 1;
            while j < KEYS.len() && KEYS[j].2.is_empty() {
                j += 1;
            }
            let names: Vec<&str> = KEYS[i..j].iter().map(|(k, _, _)| *k).collect();
            lines.push(format!("{:<22} {what}", names.join(" ")));
            i = j;
        }
        lines
    }
}

/// `1234567` as `1,234,567`.
fn group_thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn home() -> Orbit {
        Orbit {
            az: 35.0,
            el: 25.0,
            zoom: 1.0,
        }
    }

    #[test]
    fn keys_cycle_schemes_and_skip_regular_on_extraordinary_meshes() {
        let mut s = Settings::new("acc", 8, false, home());
        assert_eq!(s.scheme(), "acc");
        assert!(!s.schemes.contains(&"regular"));
        assert_eq!(s.apply(action_for("tab").unwrap()), Change::Upload);
        assert_eq!(s.scheme(), "gregory");
        s.apply(action_for("shift+tab").unwrap());
        s.apply(action_for("shift+tab").unwrap());
        assert_eq!(s.scheme(), "pccm");
        s.apply(Action::PrevScheme);
        assert_eq!(s.scheme(), "g1cc");
        s.apply(Action::PrevScheme);
        assert_eq!(s.scheme(), "gregory_osd");
        assert!(Settings::new("regular", 8, true, home())
            .schemes
            .contains(&"regular"));
    }

    #[test]
    fn levels_clamp_and_toggles_report_what_to_redo() {
        let mut s = Settings::new("pccm", 1, false, home());
        assert_eq!(s.apply(Action::LevelDown), Change::Draw);
        assert_eq!(s.level, 1);
        s.level = MAX_VIEW_LEVEL;
        s.apply(Action::LevelUp);
        assert_eq!(s.level, MAX_VIEW_LEVEL);
        assert_eq!(s.apply(Action::ToggleWireframe), Change::Draw);
        assert!(s.wireframe);
        // Scale changes re-upload only while displacing.
        assert_eq!(s.apply(Action::DisplaceMore), Change::Frame);
        assert_eq!(s.apply(Action::ToggleDisplace), Change::Upload);
        assert_eq!(s.apply(Action::DisplaceLess), Change::Upload);
        assert_eq!(s.apply(Action::NextMetric), Change::Frame);
        assert_eq!(s.metric, MetricKind::Distance(8.0));
        s.apply(Action::MetricFiner);
        assert_eq!(s.metric, MetricKind::Distance(16.0));
        s.apply(Action::Orbit(0.0, 500.0));
        assert_eq!(s.orbit.el, 89.0);
        s.apply(Action::ResetCamera);
        assert_eq!(s.orbit, home());
        assert_eq!(s.apply(Action::Quit), Change::Quit);
    }

    #[test]
    fn scripted_keys_parse_and_unknown_ones_are_named() {
        let keys = parse_keys("tab, w,comma,+").unwrap();
        assert_eq!(
            keys.0,
            vec![
                Action::NextScheme,
                Action::ToggleWireframe,
                Action::DisplaceLess,
                Action::LevelUp
            ]
        );
        let e = parse_keys("tab,ctrl+z").unwrap_err();
        assert!(e.contains("unknown key `ctrl+z`"), "{e}");
    }

    #[test]
    fn help_names_every_described_action_once() {
        let help = Settings::help_lines();
        assert_eq!(
            help.len(),
            KEYS.iter().filter(|(_, _, w)| !w.is_empty()).count()
        );
        assert!(help
            .iter()
            .any(|l| l.starts_with("+ =") && l.ends_with("level up")));
        assert!(help.iter().any(|l| l.starts_with("escape q")));
    }

    #[test]
    fn status_shows_samples_and_frame_time() {
        let s = Settings::new("pccm", 8, false, home());
        let lines = s.status(8, Some(1_234_567), 10.0);
        assert!(lines[0].starts_with("pccm  level 8"), "{lines:?}");
        assert!(
            lines[1].contains("1,234,567") && lines[1].contains("100 fps"),
            "{lines:?}"
        );
    }
}
