//! `ellipsoid plot` and `ellipsoid view`: a trajectory file (CSV or HDF5) read back and
//! drawn as a multi-panel figure (SVG or PNG, [`crate::figure`]) or as the self-contained
//! 3-D viewer page (`ellipsoid_io::viewer`). Events and the body come from the summary
//! (`--summary`, or the one stored in an HDF5 file) and the scenario it names.

use std::path::Path;
use std::process::ExitCode;

use ellipsoid_io::atomic;
use ellipsoid_io::table::{self, Table};

use crate::cli::{PlotArgs, ViewArgs};
use crate::error::CliError;
use crate::figure;

/// Reads the trajectory's columns `keep` (all if None) and, if given, the summary.
pub(crate) fn load(
    input: &Path,
    keep: Option<&[&str]>,
    summary: Option<&Path>,
) -> Result<Table, CliError> {
    let mut t = table::read_columns(input, keep).map_err(|e| CliError::Usage(e.to_string()))?;
    if let Some(p) = summary {
        let s = table::read_summary(p).map_err(|e| CliError::Usage(e.to_string()))?;
        t.apply_summary(&s, None);
    }
    Ok(t)
}

/// The default title: the file name of the scenario the summary names (the run's name;
/// never its directories, which a page must not carry), else the input file's name.
fn default_title(table: &Table, summary: Option<&Path>) -> String {
    summary
        .and_then(|p| table::read_summary(p).ok())
        .and_then(|s| {
            let named = Path::new(s.get("scenario")?.as_str()?).file_name()?;
            Some(named.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| table.source.clone())
}

/// Refuses an output whose extension is not one of `allowed` (so it cannot be the
/// input), or that is not a regular file.
pub(crate) fn check_output(
    output: &Path,
    allowed: &[&str],
    what: &str,
) -> Result<String, CliError> {
    let ext = output
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if !allowed.contains(&ext.as_str()) {
        return Err(CliError::Usage(format!(
            "{}: unknown {what} format {ext:?}; use {}",
            output.display(),
            allowed
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(" or ")
        )));
    }
    atomic::check_target(output)?;
    Ok(ext)
}

/// Writes `bytes` atomically, making the directory if needed.
pub(crate) fn put(output: &Path, bytes: &[u8]) -> Result<(), CliError> {
    if let Some(dir) = output
        .parent()
        .filter(|d| !d.as_os_str().is_empty() && !d.exists())
    {
        std::fs::create_dir_all(dir).map_err(|e| ellipsoid_io::OutputError::Io {
            path: dir.to_owned(),
            source: e,
        })?;
    }
    atomic::write(output, bytes)?;
    Ok(())
}

pub fn plot(args: &PlotArgs) -> Result<ExitCode, CliError> {
    let ext = check_output(&args.output, &["svg", "png"], "figure")?;
    let panels = match &args.columns {
        Some(columns) => figure::parse_columns(columns),
        None => figure::parse_panels(&args.panels),
    }
    .map_err(CliError::Usage)?;
    let keep = figure::columns_for(&panels);
    let table = load(&args.input, Some(&keep), args.summary.as_deref())?;
    figure::check_columns(&table, &panels).map_err(CliError::Usage)?;
    if table.shape.is_none()
        && table.contact_path().is_none()
        && panels.contains(&"path")
        && !args.quiet
    {
        eprintln!("note: {}", table.shape_note);
    }
    let title = args
        .title
        .clone()
        .unwrap_or_else(|| default_title(&table, args.summary.as_deref()));
    let svg = figure::svg(&table, &panels, &title).map_err(CliError::Plot)?;
    let bytes = if ext == "png" {
        figure::png(&svg).map_err(CliError::Plot)?
    } else {
        svg.into_bytes()
    };
    put(&args.output, &bytes)?;
    if !args.quiet {
        eprintln!(
            "wrote {} ({} panels: {}; {} rows, {} events)",
            args.output.display(),
            panels.len(),
            panels.join(", "),
            table.rows(),
            table.events.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}

pub fn view(args: &ViewArgs) -> Result<ExitCode, CliError> {
    check_output(&args.output, &["html", "htm"], "page")?;
    let keep = ellipsoid_io::viewer::COLUMNS;
    let table = load(&args.input, Some(&keep), args.summary.as_deref())?;
    let title = args
        .title
        .clone()
        .unwrap_or_else(|| default_title(&table, args.summary.as_deref()));
    let page =
        ellipsoid_io::viewer::html(&table, &title).map_err(|e| CliError::Usage(e.to_string()))?;
    if table.shape.is_none() && !args.quiet {
        eprintln!("note: {}", table.shape_note);
    }
    put(&args.output, page.as_bytes())?;
    if !args.quiet {
        let frames =
            ellipsoid_io::viewer::frame_indices(&table, ellipsoid_io::viewer::MAX_FRAMES).len();
        eprintln!(
            "wrote {} ({} rows shown as {frames} poses, {} events, {:.1} MB)",
            args.output.display(),
            table.rows(),
            table.events.len(),
            page.len() as f64 / 1e6
        );
    }
    Ok(ExitCode::SUCCESS)
}
