//! Pareto fronts of cost against error: the points no other point beats on both.

/// For each key `(cost, error)`, whether it is on the front: no other key is at least as cheap
/// and at least as accurate, and better in one of the two. `None` keys (failed runs, references)
/// are never on it and beat nothing.
pub fn pareto_front(keys: &[Option<(f64, f64)>]) -> Vec<bool> {
    keys.iter()
        .enumerate()
        .map(|(i, key)| {
            let Some((cost, loss)) = *key else {
                return false;
            };
            !keys.iter().enumerate().any(|(j, other)| {
                other.is_some_and(|(c, l)| {
                    j != i && c <= cost && l <= loss && (c < cost || l < loss)
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_and_missing_points_are_off_the_front() {
        let keys = [
            Some((1.0, 5.0)),
            Some((2.0, 5.0)), // as accurate as the first, dearer
            Some((3.0, 1.0)),
            None,
            Some((3.0, 1.0)), // a tie: neither beats the other
        ];
        assert_eq!(pareto_front(&keys), vec![true, false, true, false, true]);
    }
}
