//! The statistics of a campaign: pass rates with their Clopper–Pearson lower confidence bound,
//! and nearest-rank percentiles.
//!
//! A requirement met by `x` of `n` independent runs has a pass probability `p` whose one-sided
//! lower confidence bound at level `1 − α` is the `p` at which `x` or more passes would happen
//! with probability `α` (Clopper & Pearson, *Biometrika* 26, 1934): `P(X ≥ x | n, p) = α`, that is
//! `I_p(x, n − x + 1) = α` with `I` the regularised incomplete beta function. With no failure it
//! is `α^(1/n)`: 10 000 passes of 10 000 runs bound the rate below by 99.970 % at 95 %.

/// The one-sided `1 − alpha` lower confidence bound of a pass probability observed as
/// `passes` of `runs` (Clopper–Pearson); 0 when nothing passed (or nothing ran).
pub fn clopper_pearson_lower(passes: usize, runs: usize, alpha: f64) -> f64 {
    if passes == 0 || runs == 0 || passes > runs {
        return 0.0;
    }
    if passes == runs {
        return alpha.powf(1.0 / runs as f64);
    }
    let (a, b) = (passes as f64, (runs - passes + 1) as f64);
    // I_p(a, b) grows from 0 to 1 with p: bisection to the last bit
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if regularized_beta(mid, a, b) < alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, n = 9: about 15 digits).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // reflection
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = G
        .iter()
        .enumerate()
        .skip(1)
        .fold(G[0], |s, (i, g)| s + g / (x + i as f64));
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// The regularised incomplete beta function `I_x(a, b)` (continued fraction by the modified
/// Lentz method; Numerical Recipes §6.4), `0 ≤ x ≤ 1`, `a, b > 0`.
pub fn regularized_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_fraction(x, a, b) / a
    } else {
        1.0 - ln_front.exp() * beta_fraction(1.0 - x, b, a) / b
    }
}

/// The continued fraction of `I_x(a, b)`.
fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let not_zero = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let (mut c, mut d) = (1.0, 1.0 / not_zero(1.0 - qab * x / qap));
    let mut h = d;
    // one step of the modified Lentz method with the coefficient `aa`: the factor it multiplies h by
    let mut step = |aa: f64| {
        d = 1.0 / not_zero(1.0 + aa * d);
        c = not_zero(1.0 + aa / c);
        d * c
    };
    for m in 1..=1_000_000u32 {
        let m = f64::from(m);
        let m2 = 2.0 * m;
        h *= step(m * (b - m) * x / ((qam + m2) * (a + m2)));
        let del = step(-(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)));
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// The nearest-rank `q`-th percentile (`0 < q ≤ 100`) of `sorted` (ascending): the smallest
/// value with at least `q` % of the values at or below it; `None` when empty.
pub fn percentile(sorted: &[f64], q: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let rank = ((q / 100.0) * sorted.len() as f64).ceil() as usize;
    sorted.get(rank.clamp(1, sorted.len()) - 1).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `P(X ≥ x)` for `X ~ Binomial(n, p)`, summed term by term in logarithms.
    fn upper_tail(x: usize, n: usize, p: f64) -> f64 {
        (x..=n)
            .map(|k| {
                let k = k as f64;
                let n = n as f64;
                (ln_gamma(n + 1.0) - ln_gamma(k + 1.0) - ln_gamma(n - k + 1.0)
                    + k * p.ln()
                    + (n - k) * (1.0 - p).ln())
                .exp()
            })
            .sum()
    }

    #[test]
    fn no_failure_bound_is_alpha_to_one_over_n() {
        let b = clopper_pearson_lower(10_000, 10_000, 0.05);
        assert!((b - 0.05f64.powf(1e-4)).abs() < 1e-15);
        assert!(b > 0.99970 && b < 0.99971, "{b}");
        assert_eq!(clopper_pearson_lower(0, 10, 0.05), 0.0);
    }

    /// At the bound, `x` or more passes have probability `α` (the definition), checked by the
    /// binomial sum, for small and large campaigns.
    #[test]
    fn bound_is_where_the_binomial_tail_is_alpha() {
        for (x, n) in [
            (9, 10),
            (1, 10),
            (5, 10),
            (95, 100),
            (9_990, 10_000),
            (9_999, 10_000),
        ] {
            let p = clopper_pearson_lower(x, n, 0.05);
            let tail = upper_tail(x, n, p);
            assert!((tail - 0.05).abs() < 1e-9, "{x}/{n}: p {p}, tail {tail}");
        }
        // a value from the tables: 9 of 10, one-sided 95 %: 0.6058
        assert!((clopper_pearson_lower(9, 10, 0.05) - 0.6058).abs() < 1e-4);
    }

    #[test]
    fn ln_gamma_matches_factorials() {
        let mut f = 1.0f64;
        for n in 1..30u32 {
            f *= f64::from(n);
            assert!((ln_gamma(f64::from(n) + 1.0) - f.ln()).abs() < 1e-12 * f.ln().max(1.0));
        }
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-14);
    }

    #[test]
    fn nearest_rank_percentiles() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 50.0), Some(50.0));
        assert_eq!(percentile(&v, 95.0), Some(95.0));
        assert_eq!(percentile(&v, 99.0), Some(99.0));
        assert_eq!(percentile(&v, 100.0), Some(100.0));
        assert_eq!(percentile(&[3.0], 50.0), Some(3.0));
        assert_eq!(percentile(&[], 50.0), None);
    }
}
