//! Louca's activity index (chapter eq. 3.3): A_i = integral over the time window of |e_i f_i| dt,
//! the amplitude of the energy flow through element i; elements are then ranked by their share
//! of the total (Table 3.3).

use fmu_runtime::real::Real;

/// d A_i / dt for an element exchanging `power_w` (= e f).
///
/// ```
/// use components::activity::{activity_rate, shares_percent};
/// // Power flowing back counts as much as power flowing in: the activity integrates |e f|.
/// assert_eq!(activity_rate(-250.0), 250.0);
/// assert_eq!(shares_percent([30.0, 10.0, 60.0]), [30.0, 10.0, 60.0]);
/// ```
pub fn activity_rate<R: Real>(power_w: R) -> R {
    power_w.abs()
}

/// Each activity's share of their sum, in percent (all 0 while the sum is 0).
pub fn shares_percent<R: Real, const N: usize>(activities: [R; N]) -> [R; N] {
    let total: R = activities.iter().copied().sum();
    if total > 0.0 {
        activities.map(|a| a * 100.0 / total)
    } else {
        [R::from(0.0); N]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_sum_to_one_hundred() {
        let s = shares_percent([1.0, 3.0, 4.0]);
        assert_eq!(s, [12.5, 37.5, 50.0]);
        assert_eq!(shares_percent([0.0, 0.0]), [0.0, 0.0]);
        assert_eq!(activity_rate(-2.0), 2.0);
    }
}
