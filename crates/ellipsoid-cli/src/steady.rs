//! `ellipsoid steady`: a steady motion of a scenario's body and its linear stability, or
//! a family of them against one scenario key with its critical values
//! (docs/physics.md, "Steady motions and their stability"). SIGINT or SIGTERM stops a
//! sweep before its next value, nothing written (exit 130 or 143, `interrupt`); a value
//! the scenario refuses refuses the sweep (exit 2, nothing written).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use ellipsoid_core::body::{Body, Surface};
use ellipsoid_core::error::{ModelError, number};
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::ContactModel;
use ellipsoid_core::steady::perturb::Start;
use ellipsoid_core::steady::sweep::{MAX_VALUES, Stability};
use ellipsoid_core::steady::viscous::ViscousSpin;
use ellipsoid_core::steady::{self, Analysis, Family, Solve, Sweep};
use ellipsoid_io::atomic;
use ellipsoid_study::study::plan::Role;
use ellipsoid_study::study::table::{self, TableFormat};
use ellipsoid_study::study::{Cell, Column, Type};

use crate::cli::SteadyArgs;
#[cfg(feature = "figures")]
use crate::diagram::{self, Diagram};
use crate::error::CliError;
use crate::interrupt::Interrupt;
#[cfg(feature = "figures")]
use crate::visual::put;

pub fn steady(args: &SteadyArgs) -> Result<ExitCode, CliError> {
    let interrupt = Interrupt::install();
    let family = Family::parse(&args.family).map_err(|e| CliError::Usage(format!("--{e}")))?;
    let solve = Solve::parse(&args.solve).map_err(|e| CliError::Usage(format!("--{e}")))?;
    let scenario = crate::plausible::load(&args.scenario, &args.set, args.quiet_plausibility)?;
    if let Some(path) = &args.output {
        if let Some(plot) = &args.plot
            && same_file(path, plot)
        {
            return Err(CliError::Usage(format!(
                "-o {} and --plot {}: the table and the diagram are two files; give them different paths",
                path.display(),
                plot.display()
            )));
        }
        check_table_output(path, args.perturb.is_some())?;
    }
    let vary = args
        .vary
        .as_deref()
        .map(parse_vary)
        .transpose()
        .map_err(CliError::Usage)?;
    let plot = match &args.plot {
        Some(path) if vary.is_none() => {
            return Err(CliError::Usage(format!(
                "--plot {}: a stability diagram draws a family against a parameter; give --vary KEY=a:b:n",
                path.display()
            )));
        }
        #[cfg(not(feature = "figures"))]
        Some(_) => {
            return Err(CliError::NoFeature {
                command: "steady --plot",
                feature: "figures",
            });
        }
        #[cfg(feature = "figures")]
        Some(path) => {
            let n = vary.as_ref().map_or(0, |v| v.1.len());
            if n > diagram::MAX_VALUES {
                return Err(CliError::Usage(format!(
                    "--plot {}: a diagram draws at most {} values; --vary gives {n}",
                    path.display(),
                    diagram::MAX_VALUES
                )));
            }
            Some((path, crate::figure::Format::of(path, args.dpi)?))
        }
        None => None,
    };
    let located = |e: ModelError| CliError::from(scenario.locate(&e));
    // A sweep stopped by a signal ends in an error; the signal is what is reported.
    let swept = |e: ModelError| {
        interrupt
            .check("the sweep")
            .err()
            .unwrap_or_else(|| located(e))
    };
    let cancel = Some(interrupt.any.as_ref());
    let viscous = matches!(scenario.scene.contact, ContactModel::Viscous { .. });
    if let Some(spec) = &args.perturb {
        let (k, epsilon) = parse_perturb(spec)?;
        let start = if viscous {
            let spin = steady::viscous::analyse(&scenario.scene, family).map_err(located)?;
            perturb(&scenario, &spin, spec, k, epsilon)?
        } else {
            let an = steady::analyse_solving(&scenario.scene, family, solve).map_err(located)?;
            perturb(&scenario, &an, spec, k, epsilon)?
        };
        match &args.output {
            Some(path) => atomic::write(path, start.text.as_bytes())?,
            None => print!("{}", start.text),
        }
        return Ok(ExitCode::SUCCESS);
    }
    let viscous_modes = steady::viscous::COORDINATES.len() - 1;
    let (columns, rows) = match (vary, viscous) {
        (None, true) => {
            let spin = steady::viscous::analyse(&scenario.scene, family).map_err(located)?;
            print!("{}", describe_viscous(&spin));
            table_of(
                family,
                viscous_modes,
                "spin",
                &[spin.spin + 0.0],
                &[Ok(spin)],
            )
        }
        (None, false) => {
            let an = steady::analyse_solving(&scenario.scene, family, solve).map_err(located)?;
            print!("{}", describe(&an, solve, &scenario.scene.body));
            let modes = family.modes();
            table_of(family, modes, "spin", &[an.motion.spin], &[Ok(an)])
        }
        (Some((key, values)), true) => {
            let sw =
                steady::viscous::sweep(&scenario, family, &key, &values, cancel).map_err(swept)?;
            interrupt.check("the sweep")?;
            print!("{}", summarise(&scenario, &sw));
            draw(&scenario, &sw, plot, args.quiet)?;
            table_of(family, viscous_modes, &sw.key, &sw.values, &sw.rows)
        }
        (Some((key, values)), false) => {
            let sw = steady::sweep_solving(&scenario, family, solve, &key, &values, cancel)
                .map_err(swept)?;
            interrupt.check("the sweep")?;
            print!("{}", summarise(&scenario, &sw));
            draw(&scenario, &sw, plot, args.quiet)?;
            table_of(family, family.modes(), &sw.key, &sw.values, &sw.rows)
        }
    };
    if let Some(path) = &args.output {
        // The last moment to honour a signal: after it, the table is put in place.
        interrupt.check("the sweep")?;
        if TableFormat::from_path(path) == Ok(TableFormat::Parquet) {
            table::write(path, &columns, &rows, &scenario.source)?;
        } else {
            atomic::write(path, csv_of(&columns, &rows).as_bytes())?;
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The extensions `-o` takes: the table as CSV or Parquet, or with `--perturb` the
/// scenario as TOML (docs/steady.md). Any other is refused before anything runs, as is a
/// target that is not a regular file.
fn check_table_output(path: &std::path::Path, perturb: bool) -> Result<(), CliError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let (allowed, rule): (&[&str], &str) = if perturb {
        (
            &["toml"],
            "with --perturb, -o writes the started scenario as .toml",
        )
    } else {
        (
            &["csv", "parquet", "pq"],
            "-o writes the table as .csv or .parquet (by extension)",
        )
    };
    if !allowed.contains(&ext.as_str()) {
        return Err(CliError::Usage(format!(
            "-o {}: extension {ext:?}: {rule}",
            path.display()
        )));
    }
    if ext != "csv" && ext != "toml" {
        TableFormat::from_path(path)
            .map_err(|e| CliError::Usage(format!("-o {}: {e}", path.display())))?;
    }
    atomic::check_target(path)?;
    Ok(())
}

/// Whether `a` and `b` name the same file: the same path once made absolute and
/// normalised, or the same existing file (a link, `./x` and `x`).
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    let clean = |p: &std::path::Path| {
        std::path::absolute(p).map(|p| p.components().collect::<std::path::PathBuf>())
    };
    if let (Ok(x), Ok(y)) = (clean(a), clean(b))
        && x == y
    {
        return true;
    }
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(x), Ok(y)) if x == y
    )
}

/// Writes the stability diagram of `sw` to `plot` (its path and format), if asked.
#[cfg(feature = "figures")]
fn draw<T: Stability>(
    scenario: &Scenario,
    sw: &Sweep<T>,
    plot: Option<(&PathBuf, crate::figure::Format)>,
    quiet: bool,
) -> Result<(), CliError> {
    let Some((path, format)) = plot else {
        return Ok(());
    };
    let d = Diagram::of(sw);
    let title = format!(
        "{} family of {} against {}",
        sw.family.name(),
        scenario
            .source
            .rsplit('/')
            .next()
            .unwrap_or(&scenario.source),
        sw.key
    );
    let bytes = diagram::render(&d, &title, &format).map_err(CliError::Plot)?;
    put(path, &bytes)?;
    if !quiet {
        eprintln!(
            "wrote {} ({} values, {} critical)",
            path.display(),
            sw.values.len(),
            sw.critical.len()
        );
    }
    Ok(())
}

/// Without the `figures` feature `--plot` is refused before anything runs: nothing to draw.
#[cfg(not(feature = "figures"))]
fn draw<T: Stability>(
    _: &Scenario,
    _: &Sweep<T>,
    _: Option<(&PathBuf, String)>,
    _: bool,
) -> Result<(), CliError> {
    Ok(())
}

/// The surface a body with contact spheres rests on, a line of the description (none for
/// the paper's body, which has one surface).
fn describe_surface(o: &mut String, body: &Body, surface: Surface) {
    if !body.plain() {
        let _ = writeln!(
            o,
            "resting on           {} (the surface touching the plane)",
            body.surface_name(surface)
        );
    }
}

/// A steady spin under the viscous law in words (docs/steady.md, "Under viscous sliding").
fn describe_viscous(spin: &steady::viscous::ViscousSpin) -> String {
    let mut o = String::new();
    let z = spin.zeta.map(|x| x + 0.0);
    let _ = writeln!(
        o,
        "family               {} (viscous sliding)",
        spin.family.name()
    );
    let _ = writeln!(
        o,
        "spin n               {} rad/s (about the upward vertical)",
        spin.spin + 0.0
    );
    let _ = writeln!(o, "zeta (up, body axes) [{}, {}, {}]", z.x, z.y, z.z);
    let _ = writeln!(o, "normal force N       {} N", spin.normal_force);
    let verdict = if spin.stable() { "stable" } else { "unstable" };
    let _ = writeln!(o, "verdict              {verdict}");
    let _ = writeln!(
        o,
        "modes (eigenvalue lambda in 1/s, body frame; eigenvector in {}):",
        steady::viscous::COORDINATES.join(", ")
    );
    for ((lambda, v), name) in spin.eigenvalues.iter().zip(&spin.vectors).zip(&spin.names) {
        let v: Vec<String> = v
            .iter()
            .map(|c| format!("{:.6}{:+.6}i", c.re, c.im))
            .collect();
        let _ = writeln!(
            o,
            "  {name:<8} {:+.10e} {:+.10e}i   [{}]",
            lambda.re,
            lambda.im,
            v.join(", ")
        );
    }
    o
}

/// A column of the steady tables (every cell may be empty).
fn column(name: &str, unit: Option<&str>, ty: Type) -> Column {
    Column {
        name: name.to_owned(),
        unit: unit.map(str::to_owned),
        ty,
        nullable: true,
        role: Role::Key,
    }
}

/// Mode K's columns: lambdaK_re, lambdaK_im [1/s] and modeK.
fn mode_columns(k: usize) -> [Column; 3] {
    [
        column(&format!("lambda{k}_re"), Some("1/s"), Type::Float),
        column(&format!("lambda{k}_im"), Some("1/s"), Type::Float),
        column(&format!("mode{k}"), None, Type::Text),
    ]
}

/// `scenario` started on `motion` displaced by ε along the mode `k` of `--perturb spec`.
fn perturb<M: Start>(
    scenario: &Scenario,
    motion: &M,
    spec: &str,
    k: Mode,
    epsilon: f64,
) -> Result<Scenario, CliError> {
    let k = match k {
        Mode::Number(k) => k,
        Mode::Name(name) => {
            let names = motion.mode_names();
            names.iter().position(|m| *m == name).ok_or_else(|| {
                CliError::Usage(format!(
                    "--perturb {spec:?}: the {} motion has no mode {name:?} (its modes: {})",
                    motion.family().name(),
                    names.join(", ")
                ))
            })?
        }
    };
    Ok(steady::perturbed(scenario, motion, k, epsilon)?)
}

/// A mode of `--perturb`: its number (1-based, as in the table) or its name.
enum Mode {
    Number(usize),
    Name(String),
}

/// `MODE=EPS` of `--perturb`: the mode (0-based if a number) and ε.
fn parse_perturb(spec: &str) -> Result<(Mode, f64), CliError> {
    let rule = "--perturb takes MODE=EPS: a mode's number in the table (1 = the least stable) or its name, and the displacement, e.g. 1=1e-6";
    let bad = |why: String| CliError::Usage(format!("--perturb {spec:?}: {why}{rule}"));
    let (mode, eps) = spec.split_once('=').ok_or_else(|| bad(String::new()))?;
    let epsilon = eps
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|e| e.is_finite())
        .ok_or_else(|| bad(format!("{eps:?} is not a finite number; ")))?;
    let mode = mode.trim();
    let mode = match mode.parse::<usize>() {
        Ok(0) => return Err(bad("modes are numbered from 1; ".into())),
        Ok(k) => Mode::Number(k - 1),
        Err(_) => Mode::Name(mode.to_owned()),
    };
    Ok((mode, epsilon))
}

/// `KEY=a:b:n`: n values from a to b, evenly spaced (n = 1: a alone).
fn parse_vary(spec: &str) -> Result<(String, Vec<f64>), String> {
    let rule = "--vary takes KEY=a:b:n (n evenly spaced values from a to b), e.g. initial.psi_dot=0:200:201";
    let (key, range) = spec
        .split_once('=')
        .ok_or_else(|| format!("--vary {spec:?}: {rule}"))?;
    let parts: Vec<&str> = range.split(':').collect();
    let [a, b, n] = parts[..] else {
        return Err(format!("--vary {spec:?}: {rule}"));
    };
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("--vary {spec:?}: {s:?} is not a finite number; {rule}"))
    };
    let (a, b) = (number(a)?, number(b)?);
    let n: usize = n
        .trim()
        .parse()
        .ok()
        .filter(|n| (1..=MAX_VALUES).contains(n))
        .ok_or_else(|| {
            format!("--vary {spec:?}: the count {n:?} must be an integer from 1 to {MAX_VALUES}")
        })?;
    let values = (0..n)
        .map(|i| {
            if n == 1 {
                a
            } else {
                a + (b - a) * i as f64 / (n - 1) as f64
            }
        })
        .collect();
    Ok((key.trim().to_owned(), values))
}

/// One steady motion in words: the state (a tilted family's unknown marked as solved
/// for), then each mode.
fn describe(an: &Analysis, solve: Solve, body: &Body) -> String {
    let m = &an.motion;
    let mut o = String::new();
    // + 0.0 prints −0 (a zero times a negative spin) as 0.
    let (zeta, omega) = steady::reduce::split(&m.at.map(|x| x + 0.0));
    let _ = writeln!(o, "family               {}", m.family.name());
    describe_surface(&mut o, body, m.surface);
    let solved = |what: Solve| {
        if m.family.tilted() && solve == what {
            ", solved for"
        } else {
            ""
        }
    };
    let about = if m.family.tilted() {
        "about the body's axis"
    } else {
        "about the upward vertical"
    };
    let _ = writeln!(
        o,
        "spin n               {} rad/s ({about}{})",
        m.spin,
        solved(Solve::Spin)
    );
    let _ = writeln!(
        o,
        "tilt theta           {} rad{}",
        m.theta,
        if solve == Solve::Theta && m.family.tilted() {
            " (solved for)"
        } else {
            ""
        }
    );
    if let Some(precession) = m.precession {
        let _ = writeln!(
            o,
            "precession phi_dot   {precession} rad/s (about the vertical{})",
            solved(Solve::PhiDot)
        );
        let _ = writeln!(
            o,
            "psi_dot              {} rad/s (n - phi_dot cos theta)",
            -m.frame_rate
        );
    }
    if let Some(c) = m.circles {
        if c.center.is_infinite() {
            let _ = writeln!(
                o,
                "circles              none: G and the contact point go straight on (phi_dot = 0)"
            );
        } else {
            let _ = writeln!(
                o,
                "circles              G {} m, contact point {} m (radii about a common vertical)",
                c.center, c.contact
            );
        }
    }
    let _ = writeln!(
        o,
        "zeta (up, body axes) [{}, {}, {}]",
        zeta.x, zeta.y, zeta.z
    );
    let _ = writeln!(
        o,
        "omega (body axes)    [{}, {}, {}] rad/s",
        omega.x, omega.y, omega.z
    );
    let _ = writeln!(o, "normal force N       {} N", m.normal_force);
    if let Some(margin) = m.cone_margin {
        let _ = writeln!(o, "friction cone margin {margin} N (mu N - |F_h|)");
    }
    let verdict = if an.spectrum.stable() {
        "stable"
    } else {
        "unstable"
    };
    let _ = writeln!(o, "verdict              {verdict}");
    let _ = writeln!(
        o,
        "modes (eigenvalue lambda in 1/s, {}; eigenvector in {}):",
        if m.family.tilted() {
            "frame turning with the motion"
        } else {
            "body frame"
        },
        steady::COORDINATES.join(", ")
    );
    for mode in &an.spectrum.modes {
        let v: Vec<String> = mode
            .vector
            .iter()
            .map(|c| format!("{:.6}{:+.6}i", c.re, c.im))
            .collect();
        let _ = writeln!(
            o,
            "  {:<8} {:+.10e} {:+.10e}i   [{}]",
            mode.name,
            mode.eigenvalue.re,
            mode.eigenvalue.im,
            v.join(", ")
        );
    }
    o
}

/// A sweep in words: one line per value, then the critical values.
fn summarise<T: Stability>(scenario: &Scenario, sw: &Sweep<T>) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{} family of {} against {} ({} values)",
        sw.family.name(),
        scenario.source,
        sw.key,
        sw.values.len()
    );
    let _ = writeln!(
        o,
        "{:>16} {:>9} {:>16}  eigenvalues (1/s)",
        sw.key, "verdict", "max Re (1/s)"
    );
    for (v, row) in sw.values.iter().zip(&sw.rows) {
        match row {
            Ok(an) => {
                let ev: Vec<String> = an
                    .eigenvalues()
                    .iter()
                    .map(|z| format!("{:.6e}{:+.6e}i", z.re, z.im))
                    .collect();
                let verdict = if an.stable() { "stable" } else { "unstable" };
                let _ = writeln!(
                    o,
                    "{v:>16} {verdict:>9} {:>16.6e}  {}",
                    an.max_real(),
                    ev.join("  ")
                );
            }
            Err(e) => {
                let _ = writeln!(o, "{v:>16}  no steady motion: {e}");
            }
        }
    }
    if sw.critical.is_empty() {
        let _ = writeln!(o, "critical values: none between these values");
    }
    for c in &sw.critical {
        let _ = writeln!(
            o,
            "critical {} = {:.15e} ({}; stable {}; eigenvalue {:.6e}{:+.6e}i)",
            sw.key,
            c.value,
            c.kind.name(),
            if c.stable_above { "above" } else { "below" },
            c.eigenvalue.re,
            c.eigenvalue.im
        );
    }
    o
}

/// A row of a steady table: its motion's cells and its modes ([`Start::mode_names`],
/// [`Stability::eigenvalues`], in the same order).
trait Tabled: Stability + Start {
    /// The cells after the key: spin, theta and normal_force, then, for a tilted family,
    /// phi_dot, radius_g and radius_contact.
    fn motion_cells(&self) -> Vec<Cell>;
}

impl Tabled for Analysis {
    fn motion_cells(&self) -> Vec<Cell> {
        let m = &self.motion;
        let mut cells = vec![
            Cell::Float(m.spin + 0.0),
            Cell::Float(m.theta),
            Cell::Float(m.normal_force),
        ];
        if let (Some(precession), Some(c)) = (m.precession, m.circles) {
            cells.extend([
                Cell::Float(precession),
                Cell::Float(c.center),
                Cell::Float(c.contact),
            ]);
        }
        cells
    }
}

impl Tabled for ViscousSpin {
    fn motion_cells(&self) -> Vec<Cell> {
        vec![
            Cell::Float(self.spin + 0.0),
            Cell::Float(self.zeta.xy().norm().atan2(self.zeta.z)),
            Cell::Float(self.normal_force),
        ]
    }
}

/// The table of the steady motions of `family` (`values` of `key`, each row's motion or
/// why there is none; `modes` per row): the columns (name, SI unit, type) and the rows of
/// cells, empty where a row has no value. The columns: the key, spin, theta,
/// normal_force, for a tilted family phi_dot, radius_g and radius_contact, then stable,
/// max_real, lambdaK_re, lambdaK_im, modeK (K = 1…`modes`) and error.
fn table_of<T: Tabled>(
    family: Family,
    modes: usize,
    key: &str,
    values: &[f64],
    rows: &[steady::sweep::Row<T>],
) -> (Vec<Column>, Vec<Vec<Cell>>) {
    let mut columns = vec![
        column(key, scenario::schema::unit(key), Type::Float),
        column("spin", Some("rad/s"), Type::Float),
        column("theta", Some("rad"), Type::Float),
        column("normal_force", Some("N"), Type::Float),
    ];
    if family.tilted() {
        columns.extend([
            column("phi_dot", Some("rad/s"), Type::Float),
            column("radius_g", Some("m"), Type::Float),
            column("radius_contact", Some("m"), Type::Float),
        ]);
    }
    columns.extend([
        column("stable", None, Type::Text),
        column("max_real", Some("1/s"), Type::Float),
    ]);
    for k in 1..=modes {
        columns.extend(mode_columns(k));
    }
    columns.push(column("error", None, Type::Text));
    let cells = values
        .iter()
        .zip(rows)
        .map(|(v, row)| {
            let mut cells = vec![Cell::Float(*v)];
            match row {
                Ok(motion) => {
                    cells.extend(motion.motion_cells());
                    cells.extend([
                        Cell::Text(motion.stable().to_string()),
                        Cell::Float(motion.max_real()),
                    ]);
                    for (lambda, name) in motion.eigenvalues().iter().zip(motion.mode_names()) {
                        cells.extend([
                            Cell::Float(lambda.re),
                            Cell::Float(lambda.im),
                            Cell::Text(name.to_owned()),
                        ]);
                    }
                    cells.push(Cell::Null);
                }
                Err(e) => {
                    cells.extend(std::iter::repeat_n(Cell::Null, columns.len() - 2));
                    cells.push(Cell::Text(e.to_string()));
                }
            }
            cells
        })
        .collect();
    (columns, cells)
}

/// The table as CSV text: a header of the column names (without units), numbers in
/// their shortest round-trip form, the error quoted (RFC 4180), empty cells where there
/// is no value.
fn csv_of(columns: &[Column], rows: &[Vec<Cell>]) -> String {
    let mut o = String::new();
    let header: Vec<&str> = columns.iter().map(|c| c.name.as_str()).collect();
    let _ = writeln!(o, "{}", header.join(","));
    for row in rows {
        let cells: Vec<String> = row
            .iter()
            .zip(columns)
            .map(|(cell, c)| match cell {
                Cell::Null => String::new(),
                Cell::Float(v) => number(*v),
                Cell::Int(v) => v.to_string(),
                Cell::Text(t) if c.name == "error" => format!("\"{}\"", t.replace('"', "\"\"")),
                Cell::Text(t) => t.clone(),
            })
            .collect();
        let _ = writeln!(o, "{}", cells.join(","));
    }
    o
}
