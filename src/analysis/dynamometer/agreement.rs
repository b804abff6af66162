//! Bland–Altman agreement of a moment with M3D (thesis table 5.2): the mean difference, its
//! sample standard deviation and the 95 % limits of agreement, over the frames where M3D has
//! one sign (extension and flexion efforts apart).

/// How `other` agrees with M3D over one sign's frames; differences are other − M3D, N·m.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Agreement {
    pub frames: usize,
    /// The largest |M3D| over these frames.
    pub peak: f64,
    pub mean: f64,
    /// Sample standard deviation (n − 1); 0 for one frame.
    pub sd: f64,
    /// mean ∓ 1.96 sd.
    pub limits: [f64; 2],
    /// The largest |other − M3D| and its time, s.
    pub largest: f64,
    pub largest_time: f64,
}

/// The agreement over the frames whose M3D (`reference`) has the sign of `sign` and whose
/// `other` is a number (M2D is not where the pad's force vanishes); `None` when there are none.
pub fn agreement(times: &[f64], reference: &[f64], other: &[f64], sign: f64) -> Option<Agreement> {
    let rows: Vec<(f64, f64, f64)> = times.iter().zip(reference).zip(other).filter(|((_, &r), o)| r * sign > 0.0 && o.is_finite()).map(|((&t, &r), &o)| (t, r, o - r)).collect();
    if rows.is_empty() {
        return None;
    }
    let n = rows.len() as f64;
    let mean = rows.iter().map(|r| r.2).sum::<f64>() / n;
    let sd = if rows.len() > 1 { (rows.iter().map(|r| (r.2 - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() } else { 0.0 };
    let (largest_time, _, largest) = rows.iter().map(|&(t, r, d)| (t, r, d.abs())).fold((f64::NAN, 0.0, -1.0), |best, row| if row.2 > best.2 { row } else { best });
    Some(Agreement {
        frames: rows.len(),
        peak: rows.iter().map(|r| r.1.abs()).fold(0.0, f64::max),
        mean,
        sd,
        limits: [mean - 1.96 * sd, mean + 1.96 * sd],
        largest,
        largest_time,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// By hand: differences 1, 3 (positive M3D) give mean 2, sd √2; the negative frame is apart.
    #[test]
    fn statistics_by_hand() {
        let times = [0.0, 0.1, 0.2];
        let a = agreement(&times, &[10.0, 20.0, -5.0], &[11.0, 23.0, -9.0], 1.0).unwrap();
        assert_eq!(a.frames, 2);
        assert_relative_eq!(a.mean, 2.0);
        assert_relative_eq!(a.sd, 2f64.sqrt());
        assert_relative_eq!(a.limits[1], 2.0 + 1.96 * 2f64.sqrt());
        assert_relative_eq!(a.peak, 20.0);
        assert_eq!((a.largest, a.largest_time), (3.0, 0.1));
        let b = agreement(&times, &[10.0, 20.0, -5.0], &[11.0, 23.0, -9.0], -1.0).unwrap();
        assert_eq!((b.frames, b.mean, b.sd, b.peak), (1, -4.0, 0.0, 5.0));
        assert!(agreement(&times, &[1.0, 2.0, 3.0], &[0.0; 3], -1.0).is_none());
    }
}
