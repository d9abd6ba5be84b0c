//! `tessgen view` in a real window: an X server of its own (Xvfb, which
//! `scripts/test.sh` installs) and whatever Vulkan adapter wgpu finds
//! (lavapipe in CI). The window's frame must be `render`'s image of the same
//! view, and a scripted key sequence must change what it shows. Its usage
//! errors and the missing display are rows of docs/errors.md (cli/tests/errors.rs).

mod common;

use common::*;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};
use tessgen_runtime::render::Image;

/// An Xvfb server on a display of its own, killed on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Xvfb {
        // A display number no other server holds: chosen and taken (its
        // socket made) by one test at a time.
        static START: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _one = START.lock().unwrap_or_else(|e| e.into_inner());
        let n = (90..190)
            .find(|n| {
                !Path::new(&format!("/tmp/.X{n}-lock")).exists()
                    && !Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()
            })
            .expect("a free X display number");
        let child = Command::new("Xvfb")
            .args([
                format!(":{n}").as_str(),
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (apt-get install xvfb; scripts/test.sh installs it)");
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let start = Instant::now();
        while !socket.exists() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "Xvfb :{n} did not start"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        Xvfb {
            child,
            display: format!(":{n}"),
        }
    }

    /// `tessgen view` on this display (Wayland kept out of it).
    fn view(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_tessgen"))
            .arg("view")
            .args(args)
            .env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap()
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn load(p: &Path) -> Image {
    Image::load_png(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn window_shows_renders_image_and_keys_change_it() {
    let x = Xvfb::start();
    let dir = TempDir::new("view");
    let cube = mesh("catmark_cube.obj");
    let cube = cube.to_str().unwrap();
    let at = |name: &str| dir.path().join(name);
    let shot = |name: &str, extra: &[&str]| {
        let out = at(name);
        let mut args = vec![cube, "--size", "320x240", "--level", "8", "--no-hud"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--screenshot", out.to_str().unwrap()]);
        let o = x.view(&args);
        assert_ok(&o);
        load(&out)
    };

    // The headless render of the same view.
    let rendered = at("render.png");
    assert_ok(&tessgen([
        "render",
        cube,
        "--size",
        "320x240",
        "--level",
        "8",
        "--out",
        rendered.to_str().unwrap(),
    ]));
    let rendered = load(&rendered);

    let window = shot("window.png", &["--frames", "3"]);
    assert_eq!((window.width, window.height), (320, 240));
    let total = (window.width * window.height) as usize;
    let bad = window.count_differing(&rendered, 12);
    println!("view vs render: {bad} of {total} pixels differ by more than 12/255");
    assert!(
        bad * 200 <= total,
        "{bad} of {total} pixels differ from render's image"
    );

    // Scripted keys: the next scheme (acc) and the wireframe.
    let keyed = shot("keyed.png", &["--frames", "4", "--keys", "tab,w"]);
    let changed = keyed.count_differing(&window, 12);
    println!("after tab,w: {changed} pixels changed");
    assert!(
        changed * 50 > total,
        "tab,w changed only {changed} of {total} pixels"
    );
    // The wireframe is render's wireframe of acc.
    let acc_wire = at("acc_wire.png");
    assert_ok(&tessgen([
        "render",
        cube,
        "--scheme",
        "acc",
        "--wireframe",
        "--size",
        "320x240",
        "--level",
        "8",
        "--out",
        acc_wire.to_str().unwrap(),
    ]));
    let bad = keyed.count_differing(&load(&acc_wire), 12);
    assert!(
        bad * 200 <= total,
        "{bad} pixels differ from render --scheme acc --wireframe"
    );

    // The HUD (status and help) is drawn over the top-left corner only.
    let hud = {
        let out = at("hud.png");
        let o = x.view(&[
            cube,
            "--size",
            "640x480",
            "--frames",
            "3",
            "--keys",
            "h",
            "--screenshot",
            out.to_str().unwrap(),
        ]);
        assert_ok(&o);
        load(&out)
    };
    let white_text = hud
        .rgba
        .chunks_exact(4)
        .filter(|p| p[..3] == [255, 255, 255])
        .count();
    assert!(white_text > 500, "HUD text pixels: {white_text}");
}

#[test]
fn adaptive_and_class_colours_from_keys() {
    let x = Xvfb::start();
    let dir = TempDir::new("view-adaptive");
    let rh = mesh("catmark_righthanded.obj");
    let rh = rh.to_str().unwrap();
    let out = |name: &str, keys: &str| {
        let p = dir.path().join(name);
        let o = x.view(&[
            rh,
            "--size",
            "320x240",
            "--no-hud",
            "--frames",
            "4",
            "--keys",
            keys,
            "--screenshot",
            p.to_str().unwrap(),
        ]);
        assert_ok(&o);
        load(&p)
    };
    let uniform = out("uniform.png", "");
    let adaptive = out("adaptive.png", "a");
    let plain = out("plain.png", "c");
    let total = (uniform.width * uniform.height) as usize;
    // Class colours: orange and blue patches; plain: neither.
    let orange = |i: &Image| {
        i.rgba
            .chunks_exact(4)
            .filter(|p| i32::from(p[0]) > i32::from(p[2]) + 60)
            .count()
    };
    assert!(orange(&uniform) > total / 50, "orange patches");
    assert_eq!(orange(&plain), 0, "plain grey has no orange");
    // Adaptive draws the same surface (a few edge pixels move).
    let moved = adaptive.count_differing(&uniform, 24);
    println!("adaptive vs uniform: {moved} of {total} pixels");
    assert!(
        moved * 20 < total,
        "{moved} pixels differ between adaptive and uniform"
    );
}
