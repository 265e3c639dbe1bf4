//! `ellipsoid plot` and `ellipsoid view`: a trajectory file (CSV or HDF5) read back and
//! drawn as a multi-panel figure (SVG, PNG or PDF, [`crate::figure`]) or as the self-contained
//! 3-D viewer page (`ellipsoid_io::viewer`). Events and the body come from the summary
//! (`--summary`, or the one stored in an HDF5 file) and the scenario it names.

use std::path::Path;
#[cfg(any(feature = "figures", feature = "view"))]
use std::process::ExitCode;

use ellipsoid_io::atomic;
use ellipsoid_io::table::{self, Table};

#[cfg(feature = "figures")]
use crate::cli::PlotArgs;
#[cfg(feature = "view")]
use crate::cli::ViewArgs;
use crate::error::CliError;
#[cfg(feature = "figures")]
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

/// The default title: the file name of the scenario the run's summary names (`--summary`,
/// or the one an HDF5 file stores; never its directories, which a page must not carry),
/// else the input's file name.
#[cfg(any(feature = "figures", feature = "view"))]
fn default_title(table: &Table, input: &Path) -> String {
    table.scenario.clone().unwrap_or_else(|| {
        input.file_name().map_or_else(
            || table.source.clone(),
            |n| n.to_string_lossy().into_owned(),
        )
    })
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

#[cfg(feature = "figures")]
pub fn plot(args: &PlotArgs) -> Result<ExitCode, CliError> {
    if args.section {
        return crate::plot_section::plot_section(args);
    }
    let format = figure::Format::of(&args.output, args.dpi)?;
    let asked = match (&args.columns, &args.panels) {
        (Some(columns), _) => Some(figure::parse_columns(columns)),
        (None, Some(panels)) => Some(figure::parse_panels(panels)),
        (None, None) => None,
    }
    .transpose()
    .map_err(CliError::Usage)?;
    let every = ellipsoid_io::panels::declaration().names();
    let keep = figure::columns_for(asked.as_deref().unwrap_or(&every));
    let table = load(&args.input, Some(&keep), args.summary.as_deref())?;
    let panels = asked.unwrap_or_else(|| figure::default_panels(&table));
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
        .unwrap_or_else(|| default_title(&table, &args.input));
    let svg = figure::svg(&table, &panels, &title).map_err(CliError::Plot)?;
    let bytes = format.encode(svg).map_err(CliError::Plot)?;
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

#[cfg(feature = "view")]
pub fn view(args: &ViewArgs) -> Result<ExitCode, CliError> {
    check_output(&args.output, &["html", "htm"], "page")?;
    let asked = args
        .columns
        .as_deref()
        .map(ellipsoid_io::viewer::parse_plots)
        .transpose()
        .map_err(|rule| CliError::Usage(format!("--columns: {rule}")))?;
    let plots: Vec<&str> = match &asked {
        Some(plots) => plots.iter().map(String::as_str).collect(),
        None => [
            &ellipsoid_io::viewer::DEFAULT_PLOTS[..],
            &[ellipsoid_io::viewer::SURFACE_FORCES],
        ]
        .concat(),
    };
    let keep = ellipsoid_io::viewer::columns(&plots);
    let table = load(&args.input, Some(&keep), args.summary.as_deref())?;
    let default = ellipsoid_io::viewer::default_plots(&table);
    let plots: Vec<&str> = match &asked {
        Some(_) => plots,
        None => default.iter().map(String::as_str).collect(),
    };
    ellipsoid_io::viewer::check_plots(&table, &plots)
        .map_err(|rule| CliError::Usage(format!("--columns: {rule}")))?;
    let title = args
        .title
        .clone()
        .unwrap_or_else(|| default_title(&table, &args.input));
    let page = ellipsoid_io::viewer::html(&table, &title, &plots)
        .map_err(|e| CliError::Usage(e.to_string()))?;
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
