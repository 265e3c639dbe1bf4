//! The output columns, declared once in the core ([`ellipsoid_core::columns`]), and the
//! samples of a run turned into them.
pub use ellipsoid_core::columns::*;

/// The numeric columns of `samples` ([`Layout::numeric_columns`] order), one vector per
/// column, in one pass over the samples. Each column is allocated at its final length and
/// written by index: pushing onto 27 vectors at once (a length and capacity check per
/// value) took four times as long. Each column is its own zeroed allocation (`calloc`),
/// not a clone of a first one (`vec![column; n]` copies the zeros into every clone).
pub fn column_major(layout: &Layout, samples: &[Sample]) -> Vec<Vec<f64>> {
    let mut data: Vec<Vec<f64>> = (0..layout.numeric())
        .map(|_| vec![0.0; samples.len()])
        .collect();
    let (fixed, extra_cols) = data.split_at_mut(NUMERIC);
    let mut extra = Vec::with_capacity(layout.extra());
    for (i, s) in samples.iter().enumerate() {
        for (col, v) in fixed.iter_mut().zip(values(s)) {
            col[i] = v;
        }
        extra.clear();
        layout.surface_values(s, &mut extra);
        for (col, v) in extra_cols.iter_mut().zip(&extra) {
            col[i] = *v;
        }
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Every value of every column is the sample's own value in that column, bit for bit:
    /// the fixed columns ([`values`]) and the per-surface ones ([`Layout::surface_values`])
    /// of a body with a contact sphere.
    #[test]
    fn columns_hold_each_samples_values() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/tippe-top-stem.toml");
        let scenario =
            ellipsoid_core::scenario::load(&path, &["output.t_end=0.5", "output.dt=0.01"])
                .expect("the bundled scenario loads");
        let layout = Layout::of(&scenario.scene.body);
        assert!(layout.extra() > 0, "the scene has per-surface columns");
        let mut samples = Vec::new();
        crate::run::run(&scenario, None, "test", None, |s| {
            samples.push(*s);
            Ok::<(), std::convert::Infallible>(())
        })
        .ok()
        .expect("the run finishes");
        assert_eq!(samples.len(), 51);
        let data = column_major(&layout, &samples);
        assert_eq!(data.len(), layout.numeric());
        for (i, s) in samples.iter().enumerate() {
            let mut row = values(s).to_vec();
            layout.surface_values(s, &mut row);
            let got: Vec<u64> = data.iter().map(|col| col[i].to_bits()).collect();
            let want: Vec<u64> = row.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "sample {i}");
        }
    }
}
