//! `ellipsoid plot` and `ellipsoid view` as a user runs them: every panel drawn for a
//! bundled scene (SVG naming its axes with units; PNG not blank, with the series'
//! colours), the paths read from CSV with a summary and from HDF5, and bad input (exit 2,
//! one line naming the file, column or value, nothing written, no panic).
//! The viewer page itself is tested in a real browser: tests/browser/test_viewer.py.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .canonicalize()
        .expect("scenarios/ exists")
}

fn ellipsoid(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The tippe top (coulomb: sliding, then rolling after the slip stops at 1.1 s), 1.5 s,
/// as CSV with its summary.
fn tippe_top(dir: &Path) -> (PathBuf, PathBuf) {
    let toml = scenarios().join("tippe-top.toml");
    let o = ellipsoid(
        dir,
        &[
            "run",
            toml.to_str().unwrap(),
            "-o",
            "tt.csv",
            "--summary",
            "tt.json",
            "--set",
            "output.t_end=1.5",
            "-q",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    (dir.join("tt.csv"), dir.join("tt.json"))
}

/// Pixels of a PNG as RGBA.
fn pixels(png: &Path) -> (u32, u32, Vec<u8>) {
    let p = resvg::tiny_skia::Pixmap::load_png(png).expect("a PNG");
    (p.width(), p.height(), p.data().to_vec())
}

/// How many pixels are within 40 (per channel) of `rgb`.
fn count_near(data: &[u8], rgb: [u8; 3]) -> usize {
    data.chunks(4)
        .filter(|p| (0..3).all(|k| (i32::from(p[k]) - i32::from(rgb[k])).abs() < 40))
        .count()
}

#[test]
fn every_panel_names_its_axes_with_units_and_draws_its_data() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let cases: [(&str, &[&str], [u8; 3]); 5] = [
        ("theta", &["time t (s)", "θ (rad)"], [0x1f, 0x77, 0xb4]),
        (
            "rates",
            &[
                "time t (s)",
                "rate (rad/s)",
                "θ̇ (theta_dot)",
                "φ̇ (phi_dot)",
                "ψ̇ (psi_dot)",
                "Euler rates and the vertical spin",
                "ω_z, world (omega_world_z)",
            ],
            [0xff, 0x7f, 0x0e],
        ),
        (
            "energy",
            &[
                "time t (s)",
                "energy (J)",
                "|relative drift| (1, log)",
                "relative drift of E + W",
                "E + W",
            ],
            [0xd6, 0x27, 0x28],
        ),
        (
            "forces",
            &[
                "time t (s)",
                "normal force N (N)",
                "slip speed |v_C| (m/s)",
                "sliding orange, rolling green",
            ],
            [0xff, 0x7f, 0x0e],
        ),
        (
            "path",
            &[
                "x (m)",
                "y (m)",
                "paths on the plane",
                "G",
                "start",
                "centre C0",
                "contact point",
            ],
            [0x1f, 0x77, 0xb4],
        ),
    ];
    for (panel, labels, color) in cases {
        let svg = dir.path().join(format!("{panel}.svg"));
        let png = dir.path().join(format!("{panel}.png"));
        for out in [&svg, &png] {
            let o = ellipsoid(
                dir.path(),
                &[
                    "plot",
                    csv.to_str().unwrap(),
                    "--summary",
                    summary.to_str().unwrap(),
                    "--panels",
                    panel,
                    "-o",
                    out.to_str().unwrap(),
                ],
            );
            assert!(o.status.success(), "{panel}: {}", stderr(&o));
        }
        let text = std::fs::read_to_string(&svg).unwrap();
        for label in labels {
            assert!(
                text.contains(&label.replace('&', "&amp;")),
                "{panel}: the SVG lacks {label:?}"
            );
        }
        // The events (slip stop, mode switch at 1.1 s) are marked on every time axis.
        if panel != "path" {
            assert!(
                text.contains("stroke=\"#8040A0\""),
                "{panel}: no event line"
            );
        }
        let (w, h, data) = pixels(&png);
        assert_eq!(w, 1100, "{panel}");
        let inked = data
            .chunks(4)
            .filter(|p| p[0] < 200 || p[1] < 200 || p[2] < 200)
            .count();
        let share = inked as f64 / f64::from(w * h);
        // A rendered page, not a blank one (the title, the scenario's file name, inks
        // about 0.1 % of its own); that the data is drawn is the series colour's check below.
        assert!(
            share > 0.015,
            "{panel}: only {:.2} % of the PNG is drawn",
            100.0 * share
        );
        let n = count_near(&data, color);
        assert!(
            n > 300,
            "{panel}: {n} pixels of the series colour {color:?}: the data is not drawn"
        );
    }
    // Shading: the forces panel shows both modes' colours.
    let (_, _, data) = pixels(&dir.path().join("forces.png"));
    assert!(
        count_near(&data, [0xff, 0xe3, 0xc4]) > 1000
            && count_near(&data, [0xd4, 0xf0, 0xd4]) > 1000,
        "sliding and rolling shaded"
    );
}

/// The CSV without the columns `names` and without its comment line (a file from before
/// they existed).
fn drop_columns(csv: &Path, names: &[&str], out: &Path) {
    let text = std::fs::read_to_string(csv).unwrap();
    let rows = || text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows().next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&k| !names.contains(&header[k]))
        .collect();
    let mut o = String::new();
    for line in rows() {
        let f: Vec<&str> = line.split(',').collect();
        o.push_str(&keep.iter().map(|&k| f[k]).collect::<Vec<_>>().join(","));
        o.push('\n');
    }
    std::fs::write(out, o).unwrap();
}

#[test]
fn without_a_summary_the_contact_path_comes_from_its_columns_or_g_is_drawn_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, _) = tippe_top(dir.path());
    let plot = |input: &str| {
        let o = ellipsoid(
            dir.path(),
            &["plot", input, "--panels", "path,theta", "-o", "p.svg"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        (
            stderr(&o),
            std::fs::read_to_string(dir.path().join("p.svg")).unwrap(),
        )
    };
    // The CSV's comment line names the body: the contact path and the centre C0, no note,
    // the scenario's name as the title.
    let (err, text) = plot(csv.to_str().unwrap());
    assert!(!err.contains("note:"), "{err}");
    assert!(
        text.contains("paths on the plane")
            && text.contains("contact point")
            && text.contains("centre C0")
            && text.contains("\ntippe-top.toml\n</text>"),
        "the body and the title from the CSV alone"
    );
    // contact_x, contact_y in a file without its comment line: the contact path without
    // the body (and no C0).
    let bare = dir.path().join("bare.csv");
    drop_columns(&csv, &[], &bare);
    let (err, text) = plot(bare.to_str().unwrap());
    assert!(!err.contains("note:"), "{err}");
    assert!(
        text.contains("contact point") && !text.contains("centre C0"),
        "contact path from its columns, no centre without the body"
    );
    // An older file without them, and no summary: G's path, and the figure says why.
    let old = dir.path().join("old.csv");
    drop_columns(&csv, &["contact_x", "contact_y"], &old);
    let (err, text) = plot(old.to_str().unwrap());
    assert!(err.contains("note: body unknown"), "{err}");
    assert!(
        text.contains("paths on the plane (contact point unknown: body unknown")
            && !text.contains("contact point\n</text>"),
        "the figure says why there is no contact path"
    );
    assert!(
        !text.contains("stroke=\"#8040A0\""),
        "no events without a summary"
    );
}

/// `-o FIG.pdf`: the figure as one vector PDF page (no raster image), 1100 px wide at
/// 96 px per inch, its font embedded.
#[test]
fn plot_writes_a_vector_pdf_by_its_extension() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let o = ellipsoid(
        dir.path(),
        &[
            "plot",
            csv.to_str().unwrap(),
            "--summary",
            summary.to_str().unwrap(),
            "--panels",
            "theta,forces",
            "-o",
            "fig.pdf",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let pdf = std::fs::read(dir.path().join("fig.pdf")).unwrap();
    let text = String::from_utf8_lossy(&pdf);
    assert!(pdf.starts_with(b"%PDF-") && text.trim_end().ends_with("%%EOF"));
    assert_eq!(
        text.matches("/Type /Page\n").count()
            + text.matches("/Type /Page ").count()
            + text.matches("/Type /Page/").count(),
        1,
        "one page"
    );
    // 1100 x (40 + 2 x 300) px at 96 px per inch = 825 x 480 pt.
    assert!(text.contains("/MediaBox [0 0 825 480]"), "page size");
    assert!(text.contains("/FontFile"), "the font is embedded");
    assert!(!text.contains("/Subtype /Image"), "vector, not a picture");
    let o = ellipsoid(
        dir.path(),
        &["plot", csv.to_str().unwrap(), "-o", "fig.eps"],
    );
    assert!(!o.status.success() && stderr(&o).contains("use .svg or .png or .pdf"));
}

#[test]
fn hdf5_carries_its_own_events_and_body() {
    if !cfg!(feature = "hdf5") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let toml = scenarios().join("tippe-top.toml");
    let o = ellipsoid(
        dir.path(),
        &[
            "run",
            toml.to_str().unwrap(),
            "-o",
            "tt.h5",
            "--set",
            "output.t_end=1.5",
            "-q",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let a = ellipsoid(
        dir.path(),
        &["plot", "tt.h5", "-o", "a.svg", "--title", "x", "-q"],
    );
    let b = ellipsoid(
        dir.path(),
        &[
            "plot",
            csv.to_str().unwrap(),
            "--summary",
            summary.to_str().unwrap(),
            "-o",
            "b.svg",
            "--title",
            "x",
            "-q",
        ],
    );
    assert!(
        a.status.success() && b.status.success(),
        "{}{}",
        stderr(&a),
        stderr(&b)
    );
    let (a, b) = (
        std::fs::read_to_string(dir.path().join("a.svg")).unwrap(),
        std::fs::read_to_string(dir.path().join("b.svg")).unwrap(),
    );
    assert!(
        a == b,
        "the HDF5 file and the CSV with its summary draw the same figure"
    );
    let v = ellipsoid(
        dir.path(),
        &[
            "view",
            "tt.h5",
            "-o",
            "v.html",
            "--columns",
            "omega_world_z,slip_speed",
            "-q",
        ],
    );
    assert!(v.status.success(), "{}", stderr(&v));
    let page = std::fs::read_to_string(dir.path().join("v.html")).unwrap();
    assert!(
        page.contains("\"semi_axes\":[") && page.contains("sliding → rolling"),
        "body and events in the page"
    );
    assert!(
        page.contains("\"name\":\"omega_world_z\",\"label\":\"omega_world_z (rad/s)\"")
            && page.contains("\"name\":\"slip_speed\"")
            && !page.contains("\"name\":\"theta\""),
        "the side plots asked for, and only those"
    );
    assert!(
        page.contains("<title>tippe-top.toml</title>"),
        "titled by the scenario's name"
    );
}

#[test]
fn view_writes_one_offline_page() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let o = ellipsoid(
        dir.path(),
        &[
            "view",
            csv.to_str().unwrap(),
            "--summary",
            summary.to_str().unwrap(),
            "-o",
            "sub/v.html",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(dir.path().join("sub/v.html")).unwrap();
    assert!(page.len() > 700_000, "three.js inlined");
    assert!(
        page.contains("Copyright © 2010-2024 three.js authors"),
        "its licence inlined"
    );
    assert!(
        !page.contains("src=\"http") && !page.contains("href=\"http"),
        "nothing fetched"
    );
    assert_eq!(
        std::fs::read_dir(dir.path().join("sub")).unwrap().count(),
        1,
        "no temporary left"
    );
    // The side plots asked for are read from the CSV with what they draw from (the
    // energy's E + W needs `work`).
    let o = ellipsoid(
        dir.path(),
        &[
            "view",
            csv.to_str().unwrap(),
            "-o",
            "c.html",
            "--columns",
            "omega_world_z,energy",
            "-q",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(dir.path().join("c.html")).unwrap();
    assert!(
        page.contains("\"name\":\"omega_world_z\",\"label\":\"omega_world_z (rad/s)\"")
            && page.contains("energy E, E + W (J)"),
        "both side plots, the energy with E + W"
    );
}

#[test]
fn bad_input_is_one_line_naming_what_is_wrong_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let d = dir.path();
    std::fs::write(d.join("bad.csv"), "t,theta\n0,0.1\n0.1,zz\n").unwrap();
    std::fs::write(d.join("short.csv"), "t,theta\n0,0.1\n0.1,0.2\n").unwrap();
    std::fs::write(d.join("bad.json"), "{\"status\": 1").unwrap();
    let csv = csv.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["plot", "missing.csv", "-o", "f.svg"],
            "missing.csv: No such file",
        ),
        (
            vec!["plot", "bad.csv", "-o", "f.svg"],
            "bad.csv:3: column `theta`: \"zz\" is not a number",
        ),
        (
            vec!["plot", "short.csv", "-o", "f.svg"],
            "the rates panel needs the column `theta_dot`, which short.csv does not have",
        ),
        (
            vec![
                "plot",
                "short.csv",
                "-o",
                "f.svg",
                "--panels",
                "theta,wobble",
            ],
            "unknown panel \"wobble\"; the panels are theta, rates, energy, forces, surfaces, path",
        ),
        (
            vec!["plot", csv, "-o", "f.eps"],
            "f.eps: unknown figure format \"eps\"; use .svg or .png or .pdf",
        ),
        (
            vec!["plot", csv, "-o", csv],
            "unknown figure format \"csv\"",
        ),
        (
            vec!["plot", csv, "-o", "f.svg", "--summary", "bad.json"],
            "bad.json:1: not a JSON summary",
        ),
        (
            vec!["plot", "tt.json", "-o", "f.svg"],
            "tt.json: unknown trajectory format \"json\"",
        ),
        (
            vec!["view", "short.csv", "-o", "v.html"],
            "the viewer needs the column `x`, which short.csv does not have",
        ),
        (
            vec!["view", csv, "-o", "v.svg"],
            "unknown page format \"svg\"; use .html or .htm",
        ),
        (
            vec![
                "view",
                csv,
                "-o",
                "v.html",
                "--columns",
                "theta,omega_z_world",
            ],
            "--columns: \"omega_z_world\" is not a numeric output column; the columns are x, y",
        ),
    ];
    let _ = summary;
    for (args, want) in cases {
        let o = ellipsoid(d, &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(want) && err.trim_end().lines().count() == 1,
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    for f in ["f.svg", "f.eps", "v.html", "v.svg"] {
        assert!(!d.join(f).exists(), "{f} written");
    }
}

/// `-o ANIM.mp4` needs ffmpeg: without it the error names it and how to get it, exit 1,
/// nothing written (the GIF needs nothing).
#[test]
fn animate_mp4_without_ffmpeg_says_what_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, summary) = tippe_top(dir.path());
    let o = Command::new(BIN)
        .args(["animate", csv.to_str().unwrap(), "--summary"])
        .arg(&summary)
        .args(["-o", "top.mp4"])
        .env("ELLIPSOID_FFMPEG", dir.path().join("no-such-ffmpeg"))
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: top.mp4: MP4 needs ffmpeg, which could not be run (")
            && err.contains("no-such-ffmpeg")
            && err.contains("apt-get install ffmpeg")
            && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert!(!dir.path().join("top.mp4").exists());
}

/// A summary may come from someone else: the page it makes carries neither the content of
/// the file its `scenario` names (a parse error used to quote the file's first
/// `key = "value"` into the page's note) nor that file's directories.
#[test]
fn a_page_carries_no_local_file_content_or_directories_from_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let (with_comment, json) = tippe_top(dir.path());
    // Without the comment line, so that the body comes from the summary's scenario alone.
    let csv = dir.path().join("bare.csv");
    drop_columns(&with_comment, &[], &csv);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let secrets = tempfile::tempdir().unwrap();
    let secret = secrets.path().join("notes.toml");
    std::fs::write(&secret, "password = \"hunter2\"\n").unwrap();
    let scenario = scenarios().join("tippe-top.toml");
    for (named, note) in [
        (&secret, "body unknown: the scenario notes.toml"),
        (&scenario, "body from tippe-top.toml"),
    ] {
        let mut s = summary.clone();
        s["scenario"] = named.to_str().unwrap().into();
        std::fs::write(dir.path().join("s.json"), s.to_string()).unwrap();
        let o = ellipsoid(
            dir.path(),
            &[
                "view",
                csv.to_str().unwrap(),
                "--summary",
                "s.json",
                "-o",
                "v.html",
                "-q",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let page = std::fs::read_to_string(dir.path().join("v.html")).unwrap();
        assert!(page.contains(note), "{note}");
        assert!(!page.contains("hunter2") && !page.contains("password"));
        let parent = named.parent().unwrap().to_str().unwrap();
        assert!(!page.contains(parent), "the page names {parent}");
    }
}

/// `ellipsoid ARGS` in `dir` with its address space limited to `bytes` (`prlimit --as`).
fn capped(dir: &Path, bytes: u64, args: &[&str]) -> Output {
    Command::new("prlimit")
        .arg(format!("--as={bytes}"))
        .arg(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("prlimit runs")
}

/// Under a memory limit (`prlimit --as`) too small for the file, `view` and `plot` end
/// with one line, "out of memory", and exit 1, writing nothing; they used to abort
/// (SIGABRT, "memory allocation of … bytes failed" and a core dump). The limits start
/// where the command works on a 10-row file and rise by 4 MB steps through the 2·10⁵-row
/// file's needs. They also read only the columns they draw: the default view 11 of the 28.
#[test]
fn out_of_memory_is_a_clean_error_not_an_abort() {
    if Command::new("prlimit").arg("--version").output().is_err() {
        eprintln!("skipped: no prlimit");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let nutation = scenarios().join("nutation.toml");
    let nutation = nutation.to_str().unwrap();
    for (name, t_end) in [("small.csv", "0.009"), ("big.csv", "200")] {
        let out = ellipsoid(
            d,
            &[
                "run",
                nutation,
                "-o",
                name,
                "-q",
                "--set",
                &format!("output.t_end={t_end}"),
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    for (cmd, page) in [("view", "p.html"), ("plot", "p.png")] {
        // The smallest limit (in 4 MB steps) under which the command draws a tiny file.
        let base = (4..200u64)
            .map(|m| m << 22)
            .find(|&b| {
                capped(d, b, &[cmd, "small.csv", "-o", page, "-q"])
                    .status
                    .success()
            })
            .expect("a limit under 800 MB suffices for 10 rows");
        let mut failed = 0;
        for step in 1..=20u64 {
            let _ = std::fs::remove_file(d.join(page));
            let out = capped(d, base + (step << 22), &[cmd, "big.csv", "-o", page, "-q"]);
            let err = stderr(&out);
            match out.status.code() {
                Some(0) => break,
                Some(1) => {
                    assert!(
                        err.starts_with("error: out of memory") && err.lines().count() == 1,
                        "{cmd}: {err}"
                    );
                    assert!(!d.join(page).exists());
                    failed += 1;
                }
                other => panic!("{cmd} at {} MB: {other:?} {err}", (base >> 20) + 4 * step),
            }
        }
        assert!(failed > 0, "{cmd}: the big file never ran out of memory");
    }
}

/// `view` and `plot` refuse a CSV of more rows than a run writes (10⁷) at the row past
/// the limit, naming the file, the line and the limit, and write nothing: the line after
/// that row is not a number and is never read.
#[test]
fn view_and_plot_refuse_more_rows_than_a_run_writes_at_the_row_past_the_limit() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = ellipsoid_io::table::MAX_ROWS + 1;
    {
        let mut w = std::io::BufWriter::new(std::fs::File::create(d.join("over.csv")).unwrap());
        w.write_all(b"t\n").unwrap();
        for _ in 0..rows {
            w.write_all(b"0\n").unwrap();
        }
        w.write_all(b"not a number\n").unwrap();
        w.flush().unwrap();
    }
    for (cmd, page) in [("view", "p.html"), ("plot", "p.png")] {
        let out = ellipsoid(d, &[cmd, "over.csv", "-o", page, "-q"]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{cmd}: {err}");
        assert!(
            err.contains(&format!("over.csv:{}:", rows + 1))
                && err.contains("more than 10000000 rows")
                && !err.contains("not a number"),
            "{cmd}: {err}"
        );
        assert!(!d.join(page).exists(), "{cmd} wrote {page}");
    }
}

/// A body with contact spheres (the tippe top with its stem, through the stem's
/// touchdown at 1.372 s): its CSV (comment line) and its HDF5 file (stored scenario) both
/// give the stem back with which surface touches, and draw the same figure (the surfaces
/// panel by default) and the same page (the stem and each surface's normal force).
#[test]
fn spheres_travel_with_csv_and_hdf5_and_draw_alike() {
    use ellipsoid_io::table::{SphereShape, read};
    let dir = tempfile::tempdir().unwrap();
    let toml = scenarios().join("tippe-top-stem.toml");
    let formats: &[&str] = if cfg!(feature = "hdf5") {
        &["s.csv", "s.h5"]
    } else {
        &["s.csv"]
    };
    for out in formats {
        let o = ellipsoid(
            dir.path(),
            &[
                "run",
                toml.to_str().unwrap(),
                "-o",
                out,
                "--summary",
                "s.json",
                "--set",
                "output.t_end=1.6",
                "-q",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let t = read(&dir.path().join(out)).unwrap();
        let shape = t.shape.as_ref().expect("the body");
        assert_eq!(
            shape.spheres,
            [SphereShape {
                name: "stem".into(),
                center: [0.0, 0.0, 0.013],
                radius: 0.005
            }],
            "{out}"
        );
        let last = t.rows() - 1;
        assert_eq!(t.mode(last), Some("sliding@stem"), "{out}");
        assert_eq!(t.in_contact(last, &["ellipsoid", "stem"]), 0b10, "{out}");
        assert_eq!(t.in_contact(0, &["ellipsoid", "stem"]), 0b01, "{out}");
        let mut args = vec!["plot", out, "-o", "", "--title", "x", "-q"];
        let svg = format!("{out}.svg");
        args[3] = &svg;
        if out.ends_with(".csv") {
            args.extend(["--summary", "s.json"]);
        }
        let p = ellipsoid(dir.path(), &args);
        assert!(p.status.success(), "{}", stderr(&p));
        args[0] = "view";
        let html = format!("{out}.html");
        args[3] = &html;
        let v = ellipsoid(dir.path(), &args);
        assert!(v.status.success(), "{}", stderr(&v));
    }
    let read = |f: &str| std::fs::read_to_string(dir.path().join(f)).unwrap();
    let (svg, page) = (read("s.csv.svg"), read("s.csv.html"));
    assert!(
        svg.contains("normal force of each surface") && svg.contains("N, stem"),
        "the surfaces panel by default"
    );
    assert!(
        page.contains(r#""spheres":[{"name":"stem","center":[0.0,0.0,0.013],"radius":0.005}]"#)
            && page.contains(r#""name":"normal_force_*""#),
        "the stem and each surface's normal force on the page"
    );
    if formats.len() == 2 {
        assert!(svg == read("s.h5.svg"), "CSV and HDF5 draw the same figure");
        assert!(page == read("s.h5.html"), "CSV and HDF5 make the same page");
    }
}

/// Issue 48: `view` of a CSV of more than 10⁷ rows parsed every row (19 s for a wide
/// file) before refusing it. The rows are now counted by a scan of the bytes before any
/// is parsed: a file of 10⁷ + 1 rows of seven columns (280 MB; about 8 s to parse here)
/// is refused within 2 s, at the first row past the limit, nothing written.
#[test]
fn view_refuses_a_file_of_too_many_rows_before_parsing_it() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = ellipsoid_io::table::MAX_ROWS + 1;
    {
        let mut w = std::io::BufWriter::new(std::fs::File::create(d.join("wide.csv")).unwrap());
        w.write_all(b"t,x,y,z,theta,phi,psi\n").unwrap();
        let block = "0.5,0.5,0.5,0.5,0.5,0.5,0.5\n".repeat(1000);
        for _ in 0..rows / 1000 {
            w.write_all(block.as_bytes()).unwrap();
        }
        for _ in 0..rows % 1000 {
            w.write_all(b"0.5,0.5,0.5,0.5,0.5,0.5,0.5\n").unwrap();
        }
        w.flush().unwrap();
    }
    let start = std::time::Instant::now();
    let out = ellipsoid(d, &["view", "wide.csv", "-o", "p.html", "-q"]);
    let took = start.elapsed();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!("wide.csv:{}:", rows + 1)) && err.contains("more than 10000000 rows"),
        "{err}"
    );
    assert!(!d.join("p.html").exists());
    assert!(took < std::time::Duration::from_secs(2), "took {took:?}");
}

/// Issue 48: `animate --speed 1e-300` wrote a GIF of no frame with exit 0, and the cap of
/// 2000 frames cut a long run short without a word. An animation shows the whole run or
/// nothing: a speed at which the run needs more than 2000 frames is refused (exit 2,
/// nothing written), the message naming the cap, the frames needed and the smallest speed
/// that fits; at that speed the whole run is drawn in at most 2000 frames.
#[test]
fn animate_refuses_more_frames_than_it_draws_and_names_the_speed_that_fits() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (csv, json) = tippe_top(d);
    let animate = |speed: &str| {
        ellipsoid(
            d,
            &[
                "animate",
                csv.to_str().unwrap(),
                "--summary",
                json.to_str().unwrap(),
                "--width",
                "16",
                "--height",
                "16",
                "--speed",
                speed,
                "-o",
                "a.gif",
            ],
        )
    };
    for speed in ["1e-300", "0.01"] {
        let out = animate(speed);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{speed}: {err}");
        assert!(
            err.contains(&format!("speed = {speed}"))
                && err.contains("more than the 2000 an animation may have")
                && err.contains("give a speed of at least 0.0188"),
            "{speed}: {err}"
        );
        assert!(!d.join("a.gif").exists(), "{speed}");
    }
    // The run is 1.5 s: at 0.0188 s per s and 25 fps, 1995 frames.
    let out = animate("0.0188");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("wrote a.gif (1995 frames"),
        "{}",
        stderr(&out)
    );
}
