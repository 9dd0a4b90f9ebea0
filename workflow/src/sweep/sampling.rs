//! Samples of uncertain inputs: seeded plain random or Latin-hypercube draws in (0, 1),
//! mapped through each distribution's inverse CDF.

use rand::distributions::Open01;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

/// How the unit-cube points are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub enum Method {
    /// Independent uniform draws.
    #[serde(rename = "random")]
    Random,
    /// One draw per stratum 1/n of every input, strata paired by random permutations.
    #[serde(rename = "latin-hypercube")]
    LatinHypercube,
}

/// A distribution of an uncertain input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Uniform on [low, high].
    Uniform {
        /// Lower bound.
        low: f64,
        /// Upper bound.
        high: f64,
    },
    /// Normal with this mean and standard deviation.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
    /// Lognormal: median · exp(sigma · Z), Z standard normal (sigma is the sd of ln x).
    Lognormal {
        /// Median, exp of the mean of ln x.
        median: f64,
        /// Standard deviation of ln x.
        sigma: f64,
    },
}

impl Distribution {
    /// The value at cumulative probability `u` in (0, 1).
    pub fn quantile(self, u: f64) -> f64 {
        match self {
            // low + u·(high − low), bit for bit as before (the plan hash of a sweep started
            // with an earlier build holds); weighted where the width overflows.
            Distribution::Uniform { low, high } if (high - low).is_finite() => low + u * (high - low),
            Distribution::Uniform { low, high } => (1.0 - u) * low + u * high,
            Distribution::Normal { mean, sd } => mean + sd * inverse_normal(u),
            Distribution::Lognormal { median, sigma } => median * (sigma * inverse_normal(u)).exp(),
        }
    }

    /// The standard deviation of ln x, to first order (for the first-order output band).
    pub fn sigma_ln(self) -> f64 {
        match self {
            // (high − low)/√12 over the mean, in halves so that no sum overflows.
            Distribution::Uniform { low, high } => {
                (0.5 * high - 0.5 * low) / 3f64.sqrt() / (0.5 * low + 0.5 * high).abs()
            }
            Distribution::Normal { mean, sd } => sd / mean.abs(),
            Distribution::Lognormal { sigma, .. } => sigma,
        }
    }
}

/// `samples` points of the unit cube of dimension `dims`, seeded: `points[i][j]` in (0, 1).
pub fn unit_points(method: Method, samples: usize, dims: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut points = vec![vec![0.0; dims]; samples];
    for j in 0..dims {
        let mut strata: Vec<usize> = (0..samples).collect();
        if method == Method::LatinHypercube {
            strata.shuffle(&mut rng);
        }
        for (i, point) in points.iter_mut().enumerate() {
            let u: f64 = rng.sample(Open01);
            point[j] = match method {
                Method::Random => u,
                Method::LatinHypercube => (strata[i] as f64 + u) / samples as f64,
            };
        }
    }
    points
}

/// Φ⁻¹(u), the standard normal quantile (Acklam's rational approximation, relative error
/// below 1.2e-9).
#[allow(clippy::excessive_precision)] // Acklam's published coefficients, as printed
pub fn inverse_normal(u: f64) -> f64 {
    const A: [f64; 6] = [
        -39.696830286653757,
        220.94609842452050,
        -275.92851044696869,
        138.35775186726900,
        -30.664798066147160,
        2.5066282774592392,
    ];
    const B: [f64; 5] =
        [-54.476098798224058, 161.58583685804089, -155.69897985988661, 66.801311887719720, -13.280681552885721];
    const C: [f64; 6] = [
        -0.0077848940024302926,
        -0.32239645804113648,
        -2.4007582771618381,
        -2.5497325393437338,
        4.3746641414649678,
        2.9381639826987831,
    ];
    const D: [f64; 4] = [0.0077846957090414622, 0.32246712907003983, 2.4451341373892440, 3.7544086619074162];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if u < 0.02425 {
        tail((-2.0 * u.ln()).sqrt())
    } else if u > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - u).ln()).sqrt())
    } else {
        let q = u - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin_hypercube_puts_one_point_in_every_stratum() {
        let n = 50;
        let points = unit_points(Method::LatinHypercube, n, 4, 7);
        for j in 0..4 {
            let mut strata: Vec<usize> = points.iter().map(|p| (p[j] * n as f64) as usize).collect();
            strata.sort();
            assert_eq!(strata, (0..n).collect::<Vec<_>>());
        }
        assert_eq!(points, unit_points(Method::LatinHypercube, n, 4, 7), "seeded");
        assert_ne!(points, unit_points(Method::LatinHypercube, n, 4, 8));
    }

    #[test]
    fn quantiles_are_right() {
        assert!((inverse_normal(0.975) - 1.959963984540054).abs() < 1e-8);
        assert!((inverse_normal(0.01) + 2.3263478740408408).abs() < 1e-8);
        assert_eq!(inverse_normal(0.5), 0.0);
        let ln = Distribution::Lognormal { median: 0.3, sigma: 0.2 };
        assert!((ln.quantile(0.5) - 0.3).abs() < 1e-15);
        assert_eq!(Distribution::Uniform { low: 1.0, high: 3.0 }.quantile(0.25), 1.5);
        let wide = Distribution::Uniform { low: -1e308, high: 1e308 };
        assert_eq!((wide.quantile(0.5), wide.quantile(0.75)), (0.0, 5e307));
        let sigma = Distribution::Uniform { low: 1e308, high: 1.7e308 }.sigma_ln();
        assert!((sigma - 0.35e308 / 3f64.sqrt() / 1.35e308).abs() < 1e-15, "{sigma}");
    }
}
