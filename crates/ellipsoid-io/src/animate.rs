//! An animated GIF of a run, rendered without a browser: the body on the plane, its
//! contact trace, the time and θ in a corner (`ellipsoid animate`,
//! `Trajectory.animate`); or the same frames as an MP4, encoded by the system's ffmpeg
//! where one is installed.
//!
//! Each frame is ray-cast in an orthographic camera looking down at 30° on the plane: a
//! ray hits the ellipsoid |S⁻¹ R⁻¹(p − C0)| = 1 (S = diag(a, b, c), R the z-x-z rotation,
//! C0 = G − R g) where the quadratic in the ray parameter has a root, and is shaded by
//! Lambert's law with the surface normal R S⁻² p_b; the body's octants are coloured
//! alternately so that the spin shows, its lower half (z_b < 0) in another hue; a contact
//! sphere fixed in the body (a tippe top's stem, a top's peg) is hit where
//! |p − C0 − R c| = r and drawn grey-green, and a rim (a coin's edge) where the ray meets
//! its torus (sphere tracing; a sharp edge drawn with a tube of 1.5 % of the body) and
//! drawn brown, the nearest surface along the ray shown. Pixels
//! that miss it show the plane z = 0 (a checkerboard, one square per largest semi-axis)
//! and the contact point's path so far. The camera is fixed (the run's whole path in
//! view), so a frame differs from the last only around the body: each is written as the
//! rectangle that changed, which keeps the file small. Colours come from one fixed
//! palette, so no quantisation is needed.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{Matrix3, Vector3};

use crate::table::{Shape, Table, euler_rotation};

/// Most frames an animation may have (a minute at 25 fps, plus some).
pub const MAX_FRAMES: usize = 2_000;
/// Largest frame side, px.
pub const MAX_SIDE: u32 = 2_000;

/// What to render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Frame size, px.
    pub width: u32,
    pub height: u32,
    /// Frames per second of the animation.
    pub fps: f64,
    /// Simulated seconds per second of animation (1 = real time).
    pub speed: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            width: 480,
            height: 360,
            fps: 25.0,
            speed: 1.0,
        }
    }
}

impl Options {
    /// Checks the bounds: sides 16..=[`MAX_SIDE`] px, fps in (0, 100], speed positive
    /// and finite.
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if !(16..=MAX_SIDE).contains(&v) {
                return Err(format!("{name} = {v} px: give 16 to {MAX_SIDE} px"));
            }
        }
        if !(self.fps > 0.0 && self.fps <= 100.0) {
            return Err(format!(
                "fps = {}: give a frame rate in (0, 100] (a GIF counts in 1/100 s)",
                ellipsoid_core::error::number(self.fps)
            ));
        }
        if !(self.speed > 0.0 && self.speed.is_finite()) {
            return Err(format!(
                "speed = {}: give a positive number of simulated seconds per second",
                ellipsoid_core::error::number(self.speed)
            ));
        }
        Ok(())
    }
}

// The palette: 0 background, 1–2 the checkerboard, 3 trace, 4 text, 5 text shadow,
// then BODY_LEVELS shades of each of the four body colours.
const TRACE: u8 = 3;
const TEXT: u8 = 4;
const TEXT_BG: u8 = 5;
const BODY: u8 = 6;
const BODY_LEVELS: u8 = 40;
const BODY_COLOURS: [[f64; 3]; 6] = [
    [0.20, 0.45, 0.85], // upper half, even octants
    [0.95, 0.95, 0.98], // upper half, odd octants
    [0.90, 0.45, 0.15], // lower half, even
    [0.98, 0.85, 0.55], // lower half, odd
    [0.55, 0.68, 0.55], // a contact sphere
    [0.62, 0.50, 0.34], // a rim
];
/// The palette colour of a contact sphere (see [`BODY_COLOURS`]).
const SPHERE_COLOUR: u8 = 4;
/// The palette colour of a rim.
const RIM_COLOUR: u8 = 5;

/// A sharp rim (edge 0) is drawn as a torus with a tube of this fraction of the body's
/// largest semi-axis, so that it shows.
const SHARP_RIM_TUBE: f64 = 0.015;

/// How many of [`BODY_COLOURS`] a body's frames use: the sphere's and the rim's colours
/// only when drawn, so a one-surface body's GIF is as it always was.
fn body_colours(shape: Option<&Shape>) -> usize {
    match shape {
        Some(s) if !s.rims.is_empty() => usize::from(RIM_COLOUR) + 1,
        Some(s) if !s.spheres.is_empty() => usize::from(SPHERE_COLOUR) + 1,
        _ => usize::from(SPHERE_COLOUR),
    }
}

/// The palette of a body whose frames use the first `colours` of [`BODY_COLOURS`].
fn palette(colours: usize) -> Vec<u8> {
    let mut p = vec![
        255, 255, 255, // background
        222, 226, 232, // checker light
        200, 206, 214, // checker dark
        200, 30, 40, // trace
        20, 20, 20, // text
        255, 255, 255, // text background
    ];
    for c in &BODY_COLOURS[..colours] {
        for l in 0..BODY_LEVELS {
            let k = 0.25 + 0.75 * f64::from(l) / f64::from(BODY_LEVELS - 1);
            p.extend(c.map(|x| (255.0 * x * k).round() as u8));
        }
    }
    p
}

/// The orthographic camera: screen axes `right`, `up`, the direction `back` towards the
/// viewer, the world point at the frame's centre and px per metre.
struct Camera {
    right: Vector3<f64>,
    up: Vector3<f64>,
    back: Vector3<f64>,
    centre: Vector3<f64>,
    scale: f64,
    width: u32,
    height: u32,
}

impl Camera {
    /// Looking down at 30° from azimuth −60°, fitted to the box `lo`..`hi`.
    fn fit(lo: Vector3<f64>, hi: Vector3<f64>, width: u32, height: u32) -> Self {
        let (az, el) = (-60f64.to_radians(), 30f64.to_radians());
        let back = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let right = Vector3::new(-az.sin(), az.cos(), 0.0);
        let up = back.cross(&right);
        let centre = (lo + hi) / 2.0;
        let (mut du, mut dv) = (0f64, 0f64);
        for i in 0..8 {
            let corner = Vector3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            ) - centre;
            du = du.max(corner.dot(&right).abs());
            dv = dv.max(corner.dot(&up).abs());
        }
        let scale =
            (0.45 * f64::from(width) / du.max(1e-12)).min(0.45 * f64::from(height) / dv.max(1e-12));
        Camera {
            right,
            up,
            back,
            centre,
            scale,
            width,
            height,
        }
    }

    /// The pixel of world point `p`.
    fn pixel(&self, p: &Vector3<f64>) -> (f64, f64) {
        let d = p - self.centre;
        (
            f64::from(self.width) / 2.0 + d.dot(&self.right) * self.scale,
            f64::from(self.height) / 2.0 - d.dot(&self.up) * self.scale,
        )
    }

    /// A point on the ray through pixel (i, j), in front of the scene.
    fn origin(&self, i: u32, j: u32) -> Vector3<f64> {
        let u = (f64::from(i) + 0.5 - f64::from(self.width) / 2.0) / self.scale;
        let v = (f64::from(self.height) / 2.0 - f64::from(j) - 0.5) / self.scale;
        self.centre + self.right * u + self.up * v
    }
}

/// The body's pose in one frame.
struct Pose {
    /// Body → world rotation.
    r: Matrix3<f64>,
    /// Geometric centre C0.
    c0: Vector3<f64>,
}

impl Pose {
    fn new(shape: &Shape, g: Vector3<f64>, theta: f64, phi: f64, psi: f64) -> Self {
        let r = euler_rotation(theta, phi, psi);
        Pose {
            c0: g - r * Vector3::from(shape.com_offset),
            r,
        }
    }
}

/// The palette index of the body where the ray from `o` along −`back` first hits it (the
/// ellipsoid, a contact sphere or a rim, whichever is nearer), if it does.
fn body_pixel(shape: &Shape, pose: &Pose, o: &Vector3<f64>, back: &Vector3<f64>) -> Option<u8> {
    let inv = Vector3::from(shape.semi_axes).map(|a| 1.0 / a);
    // ray in body axes, scaled so that the ellipsoid is the unit sphere: q(s) = q0 + s w
    // (s is the distance along the ray in world units, the same for every surface)
    let q0 = (pose.r.transpose() * (o - pose.c0)).component_mul(&inv);
    let w = (pose.r.transpose() * -back).component_mul(&inv);
    // (s, palette colour, world normal) of the nearest hit
    let mut hit: Option<(f64, u8, Vector3<f64>)> = None;
    if let Some(s) = first_root(w.dot(&w), q0.dot(&w), q0.dot(&q0) - 1.0) {
        let q = q0 + w * s; // on the unit sphere; body point S q, normal ∝ S⁻¹ q
        let octant = usize::from(q.x >= 0.0) ^ usize::from(q.y >= 0.0);
        let colour = octant + if q.z < 0.0 { 2 } else { 0 };
        hit = Some((s, colour as u8, pose.r * q.component_mul(&inv).normalize()));
    }
    for sphere in &shape.spheres {
        let centre = pose.c0 + pose.r * Vector3::from(sphere.center);
        let d = o - centre;
        let r2 = sphere.radius * sphere.radius;
        if let Some(s) = first_root(1.0, -d.dot(back), d.dot(&d) - r2)
            && hit.is_none_or(|h| s < h.0)
        {
            hit = Some((s, SPHERE_COLOUR, (d - back * s).normalize()));
        }
    }
    let tube_floor = SHARP_RIM_TUBE * shape.semi_axes.iter().copied().fold(0.0, f64::max);
    for rim in &shape.rims {
        let centre = pose.c0 + pose.r * Vector3::from(rim.center);
        let q0 = pose.r.transpose() * (o - centre);
        let w = pose.r.transpose() * -back;
        if let Some((s, n)) = torus_hit(q0, w, rim.radius, rim.edge.max(tube_floor))
            && hit.is_none_or(|h| s < h.0)
        {
            hit = Some((s, RIM_COLOUR, pose.r * n));
        }
    }
    let (_, colour, n) = hit?;
    let light = Vector3::new(-0.3, -0.5, 0.8).normalize();
    let lambert = 0.35 + 0.65 * n.dot(&light).max(0.0);
    let level = (lambert * f64::from(BODY_LEVELS - 1)).round() as u8;
    Some(BODY + colour * BODY_LEVELS + level.min(BODY_LEVELS - 1))
}

/// Where the ray q0 + s w (|w| = 1, the rim's axes: its circle of radius `ring` about z
/// through the origin) first meets the torus of tube radius `tube`, and the outward
/// normal there: sphere tracing of the distance √((√(x² + y²) − R)² + z²) − r from the
/// ray's entry into the torus's bounding sphere (the distance never overshoots the
/// surface), to 1e-4 of the tube; None if the ray leaves that sphere first.
fn torus_hit(
    q0: Vector3<f64>,
    w: Vector3<f64>,
    ring: f64,
    tube: f64,
) -> Option<(f64, Vector3<f64>)> {
    let bound = ring + tube;
    let disc = q0.dot(&w).powi(2) - (q0.dot(&q0) - bound * bound);
    if disc < 0.0 {
        return None;
    }
    let (mut s, exit) = (-q0.dot(&w) - disc.sqrt(), -q0.dot(&w) + disc.sqrt());
    s = s.max(0.0);
    for _ in 0..256 {
        let q = q0 + w * s;
        let radial = q.xy().norm();
        let d = (radial - ring).hypot(q.z) - tube;
        if d < 1e-4 * tube {
            let on_ring = if radial > 0.0 {
                Vector3::new(q.x, q.y, 0.0) * (ring / radial)
            } else {
                Vector3::new(ring, 0.0, 0.0)
            };
            return Some((s, (q - on_ring).normalize()));
        }
        s += d;
        if s > exit {
            return None;
        }
    }
    None
}

/// The smaller root s of a s² + 2 b s + c = 0 (a > 0), if it has one.
fn first_root(a: f64, b: f64, c: f64) -> Option<f64> {
    let disc = b * b - a * c;
    (disc >= 0.0).then(|| (-b - disc.sqrt()) / a)
}

/// The plane's checkerboard at the ray from `o` (squares of side `square`).
fn floor_pixel(o: &Vector3<f64>, back: &Vector3<f64>, square: f64) -> u8 {
    let p = o - back * (o.z / back.z);
    let k = (p.x / square).floor() as i64 + (p.y / square).floor() as i64;
    if k.rem_euclid(2) == 0 { 1 } else { 2 }
}

/// 5×7 glyphs of the corner text, one row per byte (bit 4 leftmost).
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [14, 17, 19, 21, 25, 17, 14],
        '1' => [4, 12, 4, 4, 4, 4, 14],
        '2' => [14, 17, 1, 2, 4, 8, 31],
        '3' => [31, 2, 4, 2, 1, 17, 14],
        '4' => [2, 6, 10, 18, 31, 2, 2],
        '5' => [31, 16, 30, 1, 1, 17, 14],
        '6' => [6, 8, 16, 30, 17, 17, 14],
        '7' => [31, 1, 2, 4, 8, 8, 8],
        '8' => [14, 17, 17, 14, 17, 17, 14],
        '9' => [14, 17, 17, 15, 1, 2, 12],
        '.' => [0, 0, 0, 0, 0, 12, 12],
        '-' => [0, 0, 0, 31, 0, 0, 0],
        '=' => [0, 0, 31, 0, 31, 0, 0],
        't' => [8, 8, 28, 8, 8, 9, 6],
        's' => [0, 0, 14, 16, 14, 1, 30],
        'r' => [0, 0, 22, 25, 16, 16, 16],
        'a' => [0, 0, 14, 1, 15, 17, 15],
        'd' => [1, 1, 13, 19, 17, 17, 15],
        'θ' => [14, 17, 17, 31, 17, 17, 14],
        _ => [0; 7],
    }
}

/// Writes `text` at (x, y) with each font pixel `k`×`k` px, on a white box.
fn text(buf: &mut [u8], width: u32, height: u32, x: u32, y: u32, k: u32, text: &str) {
    let n = text.chars().count() as u32;
    let (w, h) = ((6 * n + 1) * k, 9 * k);
    for j in y..(y + h).min(height) {
        for i in x..(x + w).min(width) {
            buf[(j * width + i) as usize] = TEXT_BG;
        }
    }
    for (ci, c) in text.chars().enumerate() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..5u32 {
                if bits & (16 >> col) == 0 {
                    continue;
                }
                for dy in 0..k {
                    for dx in 0..k {
                        let i = x + (1 + 6 * ci as u32 + col) * k + dx;
                        let j = y + (1 + row as u32) * k + dy;
                        if i < width && j < height {
                            buf[(j * width + i) as usize] = TEXT;
                        }
                    }
                }
            }
        }
    }
}

/// Draws the segment a–b (pixels) `colour`, 2 px wide, where `mask` is false.
fn segment(buf: &mut [u8], mask: &[bool], width: u32, height: u32, a: (f64, f64), b: (f64, f64)) {
    let n =
        ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).clamp(1, 4 * MAX_SIDE as usize);
    for k in 0..=n {
        let f = k as f64 / n as f64;
        let (x, y) = (a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f);
        for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let (i, j) = ((x + dx - 0.5).floor(), (y + dy - 0.5).floor());
            if i >= 0.0 && j >= 0.0 && i < f64::from(width) && j < f64::from(height) {
                let at = (j as u32 * width + i as u32) as usize;
                if !mask[at] {
                    buf[at] = TRACE;
                }
            }
        }
    }
}

/// Renders the run in `table` (which needs t, x, y, z, theta, phi, psi and the body's
/// shape) as an animated GIF written to `out`: frames at t = k·speed/fps from the first
/// row to the last, at most [`MAX_FRAMES`]. Returns the number of frames, or an error
/// if `cancel` is set before a frame (read before each one).
pub fn gif(
    table: &Table,
    opt: &Options,
    out: impl Write,
    cancel: &AtomicBool,
) -> Result<usize, String> {
    let (w, h) = (opt.width, opt.height);
    let mut enc = gif::Encoder::new(
        out,
        w as u16,
        h as u16,
        &palette(body_colours(table.shape.as_ref())),
    )
    .map_err(|e| e.to_string())?;
    enc.set_repeat(gif::Repeat::Infinite)
        .map_err(|e| e.to_string())?;
    let delay = (100.0 / opt.fps).round().max(1.0) as u16;
    let mut prev: Option<Vec<u8>> = None;
    render(table, opt, cancel, |buf| {
        let frame = changed(buf, prev.as_deref(), w, h, delay);
        enc.write_frame(&frame).map_err(|e| e.to_string())?;
        prev = Some(buf.to_vec());
        Ok(())
    })
}

/// How to find ffmpeg: `$ELLIPSOID_FFMPEG`, else `ffmpeg` on the PATH.
fn ffmpeg() -> std::ffi::OsString {
    std::env::var_os("ELLIPSOID_FFMPEG").unwrap_or_else(|| "ffmpeg".into())
}

/// Renders the run as an H.264 MP4 (yuv420p, which every player reads; odd sides padded by
/// a pixel) through the system's ffmpeg, and returns its bytes and the number of frames.
/// Without ffmpeg it fails, saying what is missing and how to get it (nothing is
/// downloaded); it fails too if `cancel` is set before a frame, as [`gif`].
pub fn mp4(table: &Table, opt: &Options, cancel: &AtomicBool) -> Result<(Vec<u8>, usize), String> {
    use std::process::{Command, Stdio};
    check(table, opt)?;
    let dir = tempfile::tempdir().map_err(|e| format!("cannot make a temporary directory: {e}"))?;
    let out = dir.path().join("animation.mp4");
    let program = ffmpeg();
    let mut child = Command::new(&program)
        .args(["-hide_banner", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24"])
        .args(["-s", &format!("{}x{}", opt.width, opt.height)])
        .args(["-r", &opt.fps.to_string(), "-i", "-"])
        .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264"])
        .args(["-pix_fmt", "yuv420p", "-movflags", "+faststart", "-y"])
        .arg(&out)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "MP4 needs ffmpeg, which could not be run ({}: {e}): install it (Debian: `apt-get install ffmpeg`) or name it in ELLIPSOID_FFMPEG, or write a GIF (-o ANIM.gif)",
                program.to_string_lossy()
            )
        })?;
    let pal = palette(body_colours(table.shape.as_ref()));
    let mut stdin = child.stdin.take().expect("piped");
    let mut rgb = Vec::new();
    let rendered = render(table, opt, cancel, |buf| {
        rgb.clear();
        rgb.extend(buf.iter().flat_map(|&c| {
            let k = 3 * usize::from(c);
            [pal[k], pal[k + 1], pal[k + 2]]
        }));
        stdin
            .write_all(&rgb)
            .map_err(|e| format!("ffmpeg stopped reading frames: {e}"))
    });
    drop(stdin);
    let done = child
        .wait_with_output()
        .map_err(|e| format!("ffmpeg: {e}"))?;
    let frames = rendered.map_err(|e| {
        if done.status.success() {
            e
        } else {
            format!(
                "{e}; ffmpeg said: {}",
                String::from_utf8_lossy(&done.stderr).trim()
            )
        }
    })?;
    if !done.status.success() {
        return Err(format!(
            "ffmpeg failed ({}): {}",
            done.status,
            String::from_utf8_lossy(&done.stderr).trim()
        ));
    }
    let bytes = std::fs::read(&out).map_err(|e| format!("cannot read ffmpeg's MP4: {e}"))?;
    Ok((bytes, frames))
}

/// The columns an animation needs.
const COLUMNS: [&str; 7] = ["t", "x", "y", "z", "theta", "phi", "psi"];

/// Checks that the run can be animated with `opt` (the options' bounds, the body's shape
/// known, the columns present, a row at least), before anything is started; returns the
/// shape.
pub fn check(table: &Table, opt: &Options) -> Result<Shape, String> {
    opt.check()?;
    let shape = table
        .shape
        .clone()
        .ok_or_else(|| format!("cannot draw the body: {}", table.shape_note))?;
    let cols = table.require(&COLUMNS, "an animation")?;
    if cols[0].is_empty() {
        return Err("the trajectory has no rows".into());
    }
    frame_count(cols[0], opt)?;
    Ok(shape)
}

/// The number of frames of a run whose times are `t` (non-decreasing, at least one):
/// one at each t = t0 + k·speed/fps up to the last row (docs/scenarios.md, "ellipsoid
/// animate"). A run that needs more than [`MAX_FRAMES`] is refused, naming the speed at
/// which the whole run fits: an animation never stops short of the run's end.
pub fn frame_count(t: &[f64], opt: &Options) -> Result<usize, String> {
    use ellipsoid_core::error::number;
    let span = t[t.len() - 1] - t[0];
    let needed = if span > 0.0 {
        (span / (opt.speed / opt.fps)).floor() + 1.0
    } else {
        1.0
    };
    if needed <= MAX_FRAMES as f64 {
        return Ok(needed as usize);
    }
    // The smallest speed of three significant digits at which the run fits.
    let exact = span * opt.fps / (MAX_FRAMES - 1) as f64;
    let unit = 10f64.powf(exact.log10().floor() - 2.0);
    let up = (exact / unit).ceil() * unit;
    // Printed with its three digits (the product may carry round-off: 0.018799999999999997).
    let fits: f64 = format!("{up:.2e}").parse().unwrap_or(up);
    Err(format!(
        "speed = {}: the run's {} s at {} fps and {} simulated seconds per second need {needed:.4e} frames, more than the {MAX_FRAMES} an animation may have; give a speed of at least {} (the whole run in at most {MAX_FRAMES} frames)",
        number(opt.speed),
        number(span),
        number(opt.fps),
        number(opt.speed),
        number(fits),
    ))
}

/// Renders the frames of the run (see [`gif`]), each handed to `frame` as one palette
/// index per pixel, row by row; returns their number. Stops with an error when `cancel`
/// is set (read before each frame: a frame takes milliseconds).
fn render(
    table: &Table,
    opt: &Options,
    cancel: &AtomicBool,
    mut frame: impl FnMut(&[u8]) -> Result<(), String>,
) -> Result<usize, String> {
    let shape = check(table, opt)?;
    let cols = table.require(&COLUMNS, "an animation")?;
    let (t, x, y, z, theta, phi, psi) = (
        cols[0], cols[1], cols[2], cols[3], cols[4], cols[5], cols[6],
    );
    let t0 = t[0];
    let step = opt.speed / opt.fps;
    let frames = frame_count(t, opt)?;
    debug_assert!(frames <= MAX_FRAMES);
    let rmax = shape.semi_axes.iter().copied().fold(0.0, f64::max);
    // how far the body reaches from C0: its ellipsoid, or a contact sphere or rim beyond it
    let tube_floor = SHARP_RIM_TUBE * rmax;
    let reach0 = (shape.spheres.iter())
        .map(|s| Vector3::from(s.center).norm() + s.radius)
        .chain(
            (shape.rims.iter())
                .map(|r| Vector3::from(r.center).norm() + r.radius + r.edge.max(tube_floor)),
        )
        .fold(rmax, f64::max);
    // the box the camera keeps in view: every position of G, grown by the body
    let (mut lo, mut hi) = (
        Vector3::repeat(f64::INFINITY),
        Vector3::repeat(f64::NEG_INFINITY),
    );
    for i in 0..t.len() {
        let g = Vector3::new(x[i], y[i], z[i]);
        lo = lo.inf(&g);
        hi = hi.sup(&g);
    }
    let grow =
        Vector3::repeat(reach0 + shape.com_offset.iter().map(|v| v.abs()).fold(0.0, f64::max));
    let (lo, hi) = (Vector3::new(lo.x, lo.y, 0.0) - grow, hi + grow);
    let (w, h) = (opt.width, opt.height);
    let cam = Camera::fit(Vector3::new(lo.x, lo.y, 0.0), hi, w, h);
    let n = (w * h) as usize;
    let floor: Vec<u8> = (0..n)
        .map(|p| floor_pixel(&cam.origin(p as u32 % w, p as u32 / w), &cam.back, rmax))
        .collect();
    // the ellipsoid's lowest point; with contact spheres or rims, the contact point the run
    // wrote (on whichever surface touches)
    let written = shape.several().then(|| table.contact_path()).flatten();
    let trace: Vec<(f64, f64)> = (0..t.len())
        .map(|i| {
            let c = match &written {
                Some((cx, cy)) => [cx[i], cy[i]],
                None => {
                    let c = shape.contact_point([x[i], y[i], z[i]], theta[i], phi[i], psi[i]);
                    [c[0], c[1]]
                }
            };
            cam.pixel(&Vector3::new(c[0], c[1], 0.0))
        })
        .collect();
    let text_scale = (h / 180).max(1);
    let mut row = 0;
    for k in 0..frames {
        if cancel.load(Ordering::Relaxed) {
            return Err(format!("interrupted after {k} of {frames} frames"));
        }
        let tk = t0 + k as f64 * step;
        while row + 1 < t.len() && t[row + 1] <= tk {
            row += 1;
        }
        let pose = Pose::new(
            &shape,
            Vector3::new(x[row], y[row], z[row]),
            theta[row],
            phi[row],
            psi[row],
        );
        let mut buf = floor.clone();
        let mut mask = vec![false; n];
        // only pixels near the body can show it
        let (cx, cy) = cam.pixel(&pose.c0);
        let reach = reach0 * cam.scale + 2.0;
        let (i0, i1) = (
            (cx - reach).max(0.0) as u32,
            ((cx + reach).ceil().max(0.0) as u32).min(w),
        );
        let (j0, j1) = (
            (cy - reach).max(0.0) as u32,
            ((cy + reach).ceil().max(0.0) as u32).min(h),
        );
        for j in j0..j1 {
            for i in i0..i1 {
                if let Some(c) = body_pixel(&shape, &pose, &cam.origin(i, j), &cam.back) {
                    let at = (j * w + i) as usize;
                    buf[at] = c;
                    mask[at] = true;
                }
            }
        }
        for pair in trace[..=row].windows(2) {
            segment(&mut buf, &mask, w, h, pair[0], pair[1]);
        }
        let label = format!("t = {tk:.3} s  θ = {:.3} rad", theta[row]);
        text(&mut buf, w, h, 4, 4, text_scale, &label);
        frame(&buf)?;
    }
    Ok(frames)
}

/// The frame to write: the rectangle of `buf` that differs from `prev` (the whole frame
/// first; one pixel when nothing changed).
fn changed<'a>(buf: &'a [u8], prev: Option<&[u8]>, w: u32, h: u32, delay: u16) -> gif::Frame<'a> {
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    match prev {
        None => (x0, y0, x1, y1) = (0, 0, w, h),
        Some(p) => {
            for j in 0..h {
                for i in 0..w {
                    let at = (j * w + i) as usize;
                    if buf[at] != p[at] {
                        (x0, y0) = (x0.min(i), y0.min(j));
                        (x1, y1) = (x1.max(i + 1), y1.max(j + 1));
                    }
                }
            }
            if x1 == 0 {
                (x0, y0, x1, y1) = (0, 0, 1, 1);
            }
        }
    }
    let mut sub = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    for j in y0..y1 {
        sub.extend_from_slice(&buf[(j * w + x0) as usize..(j * w + x1) as usize]);
    }
    gif::Frame {
        left: x0 as u16,
        top: y0 as u16,
        width: (x1 - x0) as u16,
        height: (y1 - y0) as u16,
        delay,
        dispose: gif::DisposalMethod::Keep,
        buffer: sub.into(),
        ..gif::Frame::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius 1 whose centre is G, at rest upright: every pixel the camera
    /// sees within 1 m of G's image is body, none beyond (an orthographic image of a
    /// sphere is a disc of the same radius).
    #[test]
    fn a_sphere_is_a_disc_of_its_radius() {
        let shape = Shape {
            semi_axes: [1.0; 3],
            com_offset: [0.0; 3],
            spheres: Vec::new(),
            rims: Vec::new(),
            ellipsoid_contact: true,
        };
        let cam = Camera::fit(
            Vector3::new(-3.0, -3.0, 0.0),
            Vector3::new(3.0, 3.0, 3.0),
            200,
            200,
        );
        let pose = Pose::new(&shape, Vector3::new(0.0, 0.0, 1.0), 0.3, 0.2, 0.1);
        let (cx, cy) = cam.pixel(&pose.c0);
        let r = cam.scale;
        for j in 0..200 {
            for i in 0..200 {
                let d = ((f64::from(i) + 0.5 - cx).hypot(f64::from(j) + 0.5 - cy)) / r;
                let hit = body_pixel(&shape, &pose, &cam.origin(i, j), &cam.back).is_some();
                if (d - 1.0).abs() > 1e-9 {
                    assert_eq!(hit, d < 1.0, "pixel ({i}, {j}) at {d} radii");
                }
            }
        }
    }

    /// A body with a contact sphere (a peg hanging below the ellipsoid): the ray through the
    /// peg's lowest part hits it, in the sphere's colour; the ray through the ellipsoid's
    /// centre hits the ellipsoid; one beside both hits nothing.
    #[test]
    fn a_contact_sphere_is_drawn_beside_the_ellipsoid() {
        let shape = Shape {
            semi_axes: [1.0; 3],
            com_offset: [0.0; 3],
            spheres: vec![crate::table::SphereShape {
                name: "peg".into(),
                center: [0.0, 0.0, -2.0],
                radius: 0.5,
            }],
            rims: Vec::new(),
            ellipsoid_contact: true,
        };
        let cam = Camera::fit(
            Vector3::new(-4.0, -4.0, 0.0),
            Vector3::new(4.0, 4.0, 4.0),
            200,
            200,
        );
        // upright: the peg hangs 2 m below the ellipsoid's centre
        let pose = Pose::new(&shape, Vector3::new(0.0, 0.0, 2.5), 0.0, 0.0, 0.0);
        let colour = |p: Vector3<f64>| {
            let (x, y) = cam.pixel(&p);
            body_pixel(&shape, &pose, &cam.origin(x as u32, y as u32), &cam.back)
                .map(|c| (c - BODY) / BODY_LEVELS)
        };
        assert_eq!(colour(Vector3::new(0.0, 0.0, 0.15)), Some(SPHERE_COLOUR));
        assert!(colour(Vector3::new(0.0, 0.0, 2.5)).is_some_and(|c| c < SPHERE_COLOUR));
        assert_eq!(colour(Vector3::new(3.0, 3.0, 0.0)), None);
    }

    /// The torus's ray hits against its closed form: straight down through the top of the
    /// tube (at z = r), through the tube's circle at x = R + r/2 (at z = r √3/2), along x
    /// from outside (at x = −(R + r)), to 1e-4 of the tube, with the outward normal; a
    /// ray down through the hole misses.
    #[test]
    fn a_ray_meets_the_torus_where_its_closed_form_says() {
        let (ring, tube) = (1.5, 0.3);
        let down = Vector3::new(0.0, 0.0, -1.0);
        let cases = [
            (
                Vector3::new(ring, 0.0, 10.0),
                down,
                10.0 - tube,
                Vector3::z(),
            ),
            (
                Vector3::new(ring + tube / 2.0, 0.0, 10.0),
                down,
                10.0 - tube * 3f64.sqrt() / 2.0,
                Vector3::new(0.5, 0.0, 3f64.sqrt() / 2.0),
            ),
            (
                Vector3::new(-10.0, 0.0, 0.0),
                Vector3::x(),
                10.0 - ring - tube,
                -Vector3::x(),
            ),
        ];
        for (q0, w, s, n) in cases {
            let (hit, normal) = torus_hit(q0, w, ring, tube).unwrap();
            assert!((hit - s).abs() < 1e-4 * tube, "{q0:?}: {hit} against {s}");
            assert!(
                (normal - n).norm() < 1e-3,
                "{q0:?}: {normal:?} against {n:?}"
            );
        }
        assert!(torus_hit(Vector3::new(0.0, 0.0, 10.0), down, ring, tube).is_none());
    }

    /// A coin-like body (a small ellipsoid inside a rim): a ray through the rim's tube
    /// is drawn in the rim's colour, one through the centre hits the ellipsoid, one beside
    /// both hits nothing.
    #[test]
    fn a_rim_is_drawn_as_its_torus_around_the_ellipsoid() {
        let shape = Shape {
            semi_axes: [0.2; 3],
            com_offset: [0.0; 3],
            spheres: Vec::new(),
            rims: vec![crate::table::RimShape {
                name: "edge".into(),
                center: [0.0; 3],
                radius: 1.5,
                edge: 0.3,
            }],
            ellipsoid_contact: false,
        };
        let cam = Camera::fit(
            Vector3::new(-4.0, -4.0, 0.0),
            Vector3::new(4.0, 4.0, 4.0),
            400,
            400,
        );
        let pose = Pose::new(&shape, Vector3::new(0.0, 0.0, 2.0), 0.0, 0.0, 0.0);
        let colour = |p: Vector3<f64>| {
            let (x, y) = cam.pixel(&p);
            body_pixel(&shape, &pose, &cam.origin(x as u32, y as u32), &cam.back)
                .map(|c| (c - BODY) / BODY_LEVELS)
        };
        assert_eq!(colour(Vector3::new(0.0, 1.5, 2.3)), Some(RIM_COLOUR));
        assert!(colour(Vector3::new(0.0, 0.0, 2.0)).is_some_and(|c| c < SPHERE_COLOUR));
        assert_eq!(colour(Vector3::new(3.5, -3.5, 0.0)), None);
        assert_eq!(body_colours(Some(&shape)), BODY_COLOURS.len());
        assert_eq!(palette(body_colours(Some(&shape))).len(), 3 * (6 + 6 * 40));
    }

    /// A run needing more than MAX_FRAMES frames is refused, naming the smallest speed of
    /// three digits that fits (printed as such, without round-off digits) and the speed
    /// given in a short form; at that speed the whole run fits.
    #[test]
    fn frames_beyond_the_cap_are_refused_naming_the_speed_that_fits() {
        let opt = |speed| Options {
            speed,
            ..Options::default()
        };
        let t = [0.0, 0.75, 1.5];
        for speed in [0.01, 1e-300] {
            let e = frame_count(&t, &opt(speed)).unwrap_err();
            assert!(e.contains("give a speed of at least 0.0188 ("), "{e}");
            assert!(
                e.starts_with(&format!(
                    "speed = {}:",
                    ellipsoid_core::error::number(speed)
                )),
                "{e}"
            );
            assert!(e.len() < 300, "{e}");
        }
        assert_eq!(frame_count(&t, &opt(0.0188)), Ok(1995));
        assert_eq!(frame_count(&[2.0], &opt(1e-300)), Ok(1));
        for span in [1.0, 3.7, 123.456, 1e6, 1e-3] {
            let e = frame_count(&[0.0, span], &opt(1e-9)).unwrap_err();
            let fits: f64 = e
                .split("at least ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(
                frame_count(&[0.0, span], &opt(fits)).unwrap() <= MAX_FRAMES,
                "{span}: {e}"
            );
        }
    }

    #[test]
    fn options_are_bounded() {
        assert!(Options::default().check().is_ok());
        let bad = Options {
            fps: 0.0,
            ..Options::default()
        };
        assert!(bad.check().unwrap_err().contains("fps = 0"));
        let big = Options {
            width: 10_000,
            ..Options::default()
        };
        assert!(big.check().unwrap_err().contains("width = 10000 px"));
    }
}
