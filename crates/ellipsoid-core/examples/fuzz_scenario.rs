//! A mutation fuzzer for the scenario parser and validation (`scenario::parse_all` and
//! `load_all`), seeded with the bundled scenarios. It runs on stable Rust with no extra
//! tools, so the README's test command can run it on a fresh machine (cargo-fuzz needs
//! a nightly toolchain, which cannot be installed from a package registry here).
//!
//! ```text
//! cargo run --release -p ellipsoid-core --example fuzz_scenario -- --seconds 60 [--seed N]
//! ```
//! Each input is a seed scenario mutated a few times (bytes flipped, inserted, deleted;
//! lines duplicated, swapped, dropped; numbers replaced by extremes such as 5e-324, 1e308,
//! nan, 2^63; keys misspelt; tables, arrays and inline tables nested deep; two seeds
//! spliced; non-UTF-8 bytes; a `--set` override added). No coverage instrumentation: an
//! input is kept in the corpus when its outcome is new (an accepted scene, or an error of
//! a kind, key and rule not seen before), which steers mutations towards unexplored rules.
//!
//! Every input must: not panic; take under 2 s; on rejection give 1 to MAX_ERRORS errors,
//! each one line of at most 1,000 characters, in file order, with a line and column inside
//! the file; on acceptance give finite, increasing sample times ending at a finite t_end.
//! An accepted scene is also analysed by `steady` (every family and unknown, the viscous
//! spins, `linearize` at its initial state), which must not panic either, and whose every
//! analysis must have finite eigenvalues and the verdict they give.
//! A failing input is written to `target/fuzz/crashes/` and the run exits with status 1.

use std::collections::HashSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::LazyLock;
use std::time::{Duration, Instant};

use ellipsoid_core::scenario::{self, MAX_ERRORS, ScenarioErrors, schema};
use ellipsoid_core::simulate::Scene;
use ellipsoid_core::steady::{self, Family, STABLE_TOLERANCE, Solve};

/// xorshift64*: small, fast, reproducible from the printed seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Values that probe the rules: extremes, non-finite, wrong types, beyond 64 bits.
const VALUES: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "-5e-324",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775809",
    "0x7fffffffffffffff",
    "1e15",
    "1e20",
    "\"\"",
    "\"uniform\"",
    "\"rolling\"",
    "\"coulomb\"",
    "\"rk4\"",
    "true",
    "[]",
    "[1, 2]",
    "[1, 2, 3]",
    "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
    "{}",
    "{ coefficient = 1e-4 }",
    "1979-05-27T07:32:00Z",
    "[{ axis = \"x\", angle = 1 }]",
    "\"\\u00e9\"",
    "1e-9",
    "1e7",
    "3.0e-3",
];

/// Fragments of the format and of TOML syntax.
const FRAGMENTS: &[&str] = &[
    "[body]\n",
    "[initial]\n",
    "[contact]\n",
    "[effects]\n",
    "[solver]\n",
    "[output]\n",
    "[check]\n",
    "[[body]]\n",
    "[body.x]\n",
    "model = \"sliding\"\n",
    "friction = 0.3\n",
    "inertia = \"uniform\"\n",
    "theta_deg = 10\n",
    "omega_body = [0, 0, 1]\n",
    "rotation = [{ axis = \"y\", angle_deg = 0.5 }]\n",
    "times = [0.1, 0.2]\n",
    "dt = 1e-3\n",
    "step = 1e-4\n",
    "method = \"rk4\"\n",
    "velocity = [1, 0]\n",
    "air_drag = { linear = 1e-3 }\n",
    "status = \"completed\"\n",
    "energy = 1e-9\n",
    "=",
    "\"",
    "'",
    "[",
    "]",
    "{",
    "}",
    ",",
    ".",
    "#",
    "\n",
    "\\",
    "\"\"\"",
    "_deg",
    "_vector",
    "é",
    "\u{200b}",
    "\r\n",
    "\t",
];

/// Every key name of the format (from the scenario schema), for misspelling and swapping.
static KEYS: LazyLock<Vec<&'static str>> = LazyLock::new(schema::names);

fn mutate(rng: &mut Rng, input: &mut Vec<u8>, seeds: &[Vec<u8>]) {
    let len = input.len();
    match rng.below(14) {
        0 if len > 0 => {
            let i = rng.below(len);
            input[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(len + 1);
            input.insert(i, rng.next() as u8);
        }
        2 if len > 0 => {
            let i = rng.below(len);
            let n = rng.below(16.min(len - i)) + 1;
            input.drain(i..i + n);
        }
        3 => {
            let i = rng.below(len + 1);
            let f = rng.pick(FRAGMENTS).as_bytes();
            input.splice(i..i, f.iter().copied());
        }
        4 | 5 => {
            // A number or value replaced by a probing one.
            let text = String::from_utf8_lossy(input).into_owned();
            let starts: Vec<usize> = text.match_indices(" = ").map(|(i, _)| i + 3).collect();
            if !starts.is_empty() {
                let s = *rng.pick(&starts);
                let end = text[s..].find('\n').map_or(text.len(), |e| s + e);
                *input = format!("{}{}{}", &text[..s], rng.pick(VALUES), &text[end..]).into_bytes();
            }
        }
        6 => {
            // A key misspelt or swapped for another.
            let text = String::from_utf8_lossy(input).into_owned();
            let k = rng.pick(&KEYS);
            let at: Vec<usize> = text
                .match_indices(&format!("\n{k} "))
                .map(|(i, _)| i + 1)
                .collect();
            if !at.is_empty() {
                let i = *rng.pick(&at);
                let typo = match rng.below(3) {
                    0 => format!("{k}{k}"),
                    1 => k[1..].to_owned(),
                    _ => rng.pick(&KEYS).to_string(),
                };
                *input = format!("{}{typo}{}", &text[..i], &text[i + k.len()..]).into_bytes();
            }
        }
        7 => {
            // Lines: duplicate, drop or swap one.
            let mut lines: Vec<Vec<u8>> =
                input.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect();
            let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
            match rng.below(3) {
                0 => {
                    let l = lines[i].clone();
                    lines.insert(j, l);
                }
                1 => {
                    lines.remove(i);
                }
                _ => lines.swap(i, j),
            }
            *input = lines.join(&b'\n');
        }
        8 => {
            // Deep nesting, of arrays or inline tables.
            let depth = [4, 40, 200, 3000][rng.below(4)];
            let (open, close) = if rng.below(2) == 0 {
                ("[", "]")
            } else {
                ("{ x = ", " }")
            };
            let v = format!("{}1{}", open.repeat(depth), close.repeat(depth));
            *input = format!("{}\nextra = {v}\n", String::from_utf8_lossy(input)).into_bytes();
        }
        9 => {
            // Splice with another seed.
            let other = rng.pick(seeds);
            let cut = rng.below(len + 1);
            let from = rng.below(other.len() + 1);
            input.truncate(cut);
            input.extend_from_slice(&other[from..]);
        }
        10 => {
            // A long key or value (messages must stay short and fast).
            let n = [100, 10_000, 1_000_000][rng.below(3)];
            let i = rng.below(len + 1);
            let long = if rng.below(2) == 0 {
                format!("\n{} = 1\n", "k".repeat(n))
            } else {
                format!("\nnote = \"{}\"\n", "v".repeat(n))
            };
            input.splice(i..i, long.into_bytes());
        }
        11 => {
            // Non-UTF-8 bytes.
            let i = rng.below(len + 1);
            input.splice(
                i..i,
                [0xff, 0xc3, 0x28, 0xe9][..rng.below(4) + 1].iter().copied(),
            );
        }
        12 if len > 0 => input.truncate(rng.below(len)),
        _ => {
            let i = rng.below(len + 1);
            let v = rng.pick(VALUES);
            input.splice(i..i, v.bytes());
        }
    }
}

/// Overrides sometimes given with an input.
fn overrides(rng: &mut Rng) -> Vec<String> {
    match rng.below(6) {
        0 => {
            // A key of the schema, its array tables' first element (`body.sphere[0]`).
            let k = rng.pick(schema::SCHEMA);
            let table = match k.table {
                "" => String::new(),
                t if schema::find(t).is_some_and(|t| t.kind == schema::Kind::Tables) => {
                    format!("{t}[0].")
                }
                t => format!("{t}."),
            };
            vec![format!("{table}{}={}", k.name, rng.pick(VALUES))]
        }
        1 => vec![format!(
            "output.times=[{}]",
            (0..rng.below(5000))
                .map(|i| (i as f64 * 1e-4).to_string())
                .collect::<Vec<_>>()
                .join(",")
        )],
        2 => vec![
            rng.pick(&[
                "x",
                "=1",
                "a..b=1",
                "body.mass",
                "body.mass.x=1",
                "output.dt=[1,",
            ])
            .to_string(),
        ],
        _ => Vec::new(),
    }
}

/// What an outcome looks like, for novelty: accepted, or each error's kind, key and rule head.
fn outcome_shape(result: &Result<scenario::Scenario, ScenarioErrors>) -> String {
    match result {
        Ok(s) => format!(
            "ok {:?} {}",
            s.scene.contact,
            s.scene.sample_times.len().min(3)
        ),
        Err(errs) => errs
            .0
            .iter()
            .map(|e| {
                format!(
                    "{:?} {:?} {}",
                    e.kind,
                    e.key
                        .as_deref()
                        .map(|k| k.chars().take(40).collect::<String>()),
                    e.rule.chars().take(30).collect::<String>()
                )
            })
            .collect::<Vec<_>>()
            .join("|"),
    }
}

/// `steady` of an accepted scene: every family, solving for each unknown, and the viscous
/// spins; `linearize` at the initial state. Err(why) if an analysis has a non-finite
/// eigenvalue or a verdict its eigenvalues do not give (stable exactly when no real part
/// is above `STABLE_TOLERANCE` of the scale).
fn check_steady(scene: &Scene) -> Result<(), String> {
    let verdict = |what: String, eigenvalues: Vec<nalgebra::Complex<f64>>, stable, scale: f64| {
        let max_real = eigenvalues
            .iter()
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max);
        if !eigenvalues
            .iter()
            .all(|l| l.re.is_finite() && l.im.is_finite())
            || !scale.is_finite()
        {
            return Err(format!(
                "{what}: eigenvalues {eigenvalues:?}, scale {scale}"
            ));
        }
        if stable != (max_real <= STABLE_TOLERANCE * scale) {
            return Err(format!("{what}: verdict {stable} against {eigenvalues:?}"));
        }
        Ok(())
    };
    for family in [
        Family::Upright,
        Family::Inverted,
        Family::Precession,
        Family::RollingCircle,
    ] {
        for solve in [Solve::Spin, Solve::PhiDot, Solve::Theta] {
            if let Ok(an) = steady::analyse_solving(scene, family, solve) {
                let s = &an.spectrum;
                verdict(
                    format!("steady {family:?} {solve:?}"),
                    s.eigenvalues(),
                    s.stable(),
                    s.scale(),
                )?;
            }
        }
        if let Ok(spin) = steady::viscous::analyse(scene, family) {
            verdict(
                format!("viscous {family:?}"),
                spin.eigenvalues.clone(),
                spin.stable(),
                spin.scale(),
            )?;
        }
    }
    if let Ok(lin) = steady::linearize_scene(scene, None)
        && !lin.jacobian.iter().all(|x| x.is_finite())
    {
        return Err(format!("linearize: {}", lin.jacobian));
    }
    Ok(())
}

/// Checks an outcome; Err(why) if it breaks a property.
fn check(
    text: Option<&str>,
    result: &Result<scenario::Scenario, ScenarioErrors>,
    took: Duration,
) -> Result<(), String> {
    if took > Duration::from_secs(2) {
        return Err(format!("took {took:?}"));
    }
    match result {
        Ok(s) => {
            let t = &s.scene.sample_times;
            if !(s.scene.t_end.is_finite() && s.scene.t_end > 0.0) {
                return Err(format!("accepted t_end = {}", s.scene.t_end));
            }
            if t.is_empty() || t.iter().any(|x| !x.is_finite()) || t.windows(2).any(|w| w[0] > w[1])
            {
                return Err(
                    "accepted sample times that are empty, non-finite or decreasing".into(),
                );
            }
        }
        Err(errs) => {
            let errs = &errs.0;
            if errs.is_empty() || errs.len() > MAX_ERRORS {
                return Err(format!("{} errors", errs.len()));
            }
            let lines = text.map(|t| t.lines().count() + 1);
            let mut last = (false, 0, 0);
            for e in errs {
                let msg = e.to_string();
                if msg.contains('\n') || msg.chars().count() > 1000 {
                    return Err(format!(
                        "message of {} characters or on several lines: {}",
                        msg.chars().count(),
                        msg.chars().take(300).collect::<String>()
                    ));
                }
                if let (Some(line), Some(max)) = (e.location.line, lines)
                    && line > max
                {
                    return Err(format!("line {line} beyond the file's {max}: {msg}"));
                }
                let place = (
                    e.location.line.is_none(),
                    e.location.line.unwrap_or(0),
                    e.location.column.unwrap_or(0),
                );
                if place < last {
                    return Err(format!("errors out of file order at: {msg}"));
                }
                last = place;
            }
        }
    }
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .map(|v| {
                v.parse::<u64>()
                    .unwrap_or_else(|_| panic!("{name} takes a number"))
            })
    };
    let seconds = arg("--seconds").unwrap_or(60);
    let seed = arg("--seed").unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.as_nanos() as u64)
            | 1
    });
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut seeds: Vec<Vec<u8>> = Vec::new();
    let mut stack = vec![root.join("scenarios")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).expect("scenarios/").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                seeds.push(std::fs::read(&p).expect("a seed"));
            }
        }
    }
    let crashes = root.join("target/fuzz/crashes");
    let scratch = std::env::temp_dir().join(format!("ellipsoid-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch dir");
    // Quiet panics: a panic is reported as a finding, with its message.
    std::panic::set_hook(Box::new(|_| {}));
    println!(
        "fuzz_scenario: {} seeds, seed {seed}, {seconds} s",
        seeds.len()
    );
    let mut rng = Rng(seed);
    let mut corpus = seeds.clone();
    let mut seen: HashSet<String> = HashSet::new();
    let (start, budget) = (Instant::now(), Duration::from_secs(seconds));
    let (mut runs, mut accepted) = (0u64, 0u64);
    while start.elapsed() < budget {
        let mut input = rng.pick(&corpus).clone();
        for _ in 0..rng.below(4) + 1 {
            mutate(&mut rng, &mut input, &seeds);
        }
        input.truncate(4 << 20);
        let sets = overrides(&mut rng);
        let text = std::str::from_utf8(&input).ok().map(str::to_owned);
        let t0 = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| match &text {
            Some(t) => scenario::parse_all(t, "fuzz.toml", &sets),
            None => {
                let path = scratch.join("fuzz.toml");
                std::fs::write(&path, &input).expect("scratch file");
                scenario::load_all(&path, &sets)
            }
        }));
        let steady = match &result {
            Ok(Ok(s)) => {
                catch_unwind(AssertUnwindSafe(|| check_steady(&s.scene))).unwrap_or_else(|p| {
                    Err(format!(
                        "steady panicked: {}",
                        ellipsoid_core::error::panic_message(&*p)
                    ))
                })
            }
            _ => Ok(()),
        };
        let took = t0.elapsed();
        runs += 1;
        let verdict = match &result {
            Ok(r) => check(text.as_deref(), r, took).and(steady),
            Err(p) => Err(format!(
                "panic: {}",
                ellipsoid_core::error::panic_message(p)
            )),
        };
        if let Err(why) = verdict {
            std::fs::create_dir_all(&crashes).expect("crash dir");
            let name: PathBuf = crashes.join(format!("crash-{seed}-{runs}.toml"));
            std::fs::write(&name, &input).expect("crash file");
            std::fs::write(name.with_extension("set"), sets.join("\n")).expect("crash overrides");
            eprintln!(
                "fuzz_scenario: FAILED after {runs} inputs: {why}\n  input: {} (overrides beside it, .set); reproduce with --seed {seed}",
                name.display()
            );
            let _ = std::fs::remove_dir_all(&scratch);
            std::process::exit(1);
        }
        if let Ok(r) = &result {
            accepted += u64::from(r.is_ok());
            if seen.insert(outcome_shape(r)) && input.len() < 64 << 10 {
                corpus.push(input);
            }
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    println!(
        "fuzz_scenario: {runs} inputs ({accepted} accepted), {} distinct outcomes, corpus {}: no failure",
        seen.len(),
        corpus.len()
    );
}
