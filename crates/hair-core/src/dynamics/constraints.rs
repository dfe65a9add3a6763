//! Segment-length constraints: the mass-weighted projection (fast projection), follow-the-leader
//! projection of positions, and removal of the stretching part of velocities.

use glam::{Vec3, Vec4};

/// Mass-weighted projection of one chain onto its segment lengths by `iterations` Newton steps of
/// the fast projection (Goldenthal et al. 2007): with `C_i = |x_i − x_{i−1}| − l_i`, unit segment
/// directions `u_i` and inverse masses `w`, solve the tridiagonal system
/// `(w_{i−1} + w_i)·λ_i − w_{i−1}(u_{i−1}·u_i)·λ_{i−1} − w_i(u_i·u_{i+1})·λ_{i+1} = C_i` and move
/// `x_i −= w_i·(u_i·λ_i − u_{i+1}·λ_{i+1})`. It keeps the centre of mass (momentum) and removes
/// the stretch along the constraint gradients only, so a velocity taken from the projected
/// positions does not gain energy. `inverse_masses[0]` is 0 for an attached root.
/// `directions` and `work` are scratch of the chain's node count. Converges quadratically; the
/// caller finishes with [`follow_the_leader`] for the last rounding.
pub fn project_lengths(
    positions: &mut [Vec3],
    inverse_masses: impl Fn(usize) -> f32,
    rest_lengths: &[f32],
    directions: &mut [Vec3],
    work: &mut [Vec4],
    iterations: usize,
) {
    let n = positions.len();
    if n < 2 {
        return;
    }
    for _ in 0..iterations {
        // Directions and violations of every segment i = 1..n.
        for i in 1..n {
            let segment = positions[i] - positions[i - 1];
            let length = segment.length();
            directions[i] = if length > 1e-12 {
                segment / length
            } else {
                Vec3::ZERO
            };
            work[i].w = length - rest_lengths[i];
        }
        // Converged (or at rest): a step below the rounding of the positions would only add noise.
        if (1..n).all(|i| work[i].w.abs() <= LENGTH_TOLERANCE * rest_lengths[i]) {
            return;
        }
        // Thomas algorithm: work[i] = (diagonal, off-diagonal to i+1, c', d').
        let mut previous_c = 0.0f32;
        let mut previous_d = 0.0f32;
        let mut previous_off = 0.0f32;
        for i in 1..n {
            let diagonal = inverse_masses(i - 1) + inverse_masses(i);
            let off = if i + 1 < n {
                -inverse_masses(i) * directions[i].dot(directions[i + 1])
            } else {
                0.0
            };
            let pivot = diagonal - previous_off * previous_c;
            if pivot.is_nan() || pivot.abs() <= 1e-30 {
                return;
            }
            let c = off / pivot;
            let d = (work[i].w - previous_off * previous_d) / pivot;
            work[i] = Vec4::new(diagonal, off, c, d);
            previous_c = c;
            previous_d = d;
            previous_off = off;
        }
        // Back substitution: λ_i stored in work[i].w.
        let mut next_lambda = 0.0f32;
        for i in (1..n).rev() {
            let lambda = work[i].w - work[i].z * next_lambda;
            work[i].w = lambda;
            next_lambda = lambda;
        }
        for i in 0..n {
            let w = inverse_masses(i);
            if w == 0.0 {
                continue;
            }
            let mut delta = Vec3::ZERO;
            if i >= 1 {
                delta += directions[i] * work[i].w;
            }
            if i + 1 < n {
                delta -= directions[i + 1] * work[i + 1].w;
            }
            positions[i] -= delta * w;
        }
    }
}

/// Follow-the-leader (FTL) projection, root to tip: `x_i ← x_{i−1} + l_i·(x_i − x_{i−1})/|…|`.
/// Every segment gets its rest length `rest_lengths[i]` [m] in one pass; node 0 is not moved.
/// Segments already within [`LENGTH_TOLERANCE`] of their length are left as they are, so that a
/// chain at rest is not perturbed by the rounding of recomputed positions (which, divided by a
/// short substep, would read as velocity noise). A zero-length segment keeps the previous
/// segment's direction. Returns nothing; the corrections are `x_i' − x_i`.
#[inline]
pub fn follow_the_leader(positions: &mut [Vec3], rest_lengths: &[f32]) {
    let mut previous_direction = Vec3::ZERO;
    for i in 1..positions.len() {
        let segment = positions[i] - positions[i - 1];
        let length = segment.length();
        let direction = if length > 1e-12 {
            segment / length
        } else {
            previous_direction
        };
        if (length - rest_lengths[i]).abs() > LENGTH_TOLERANCE * rest_lengths[i] {
            positions[i] = positions[i - 1] + direction * rest_lengths[i];
        }
        previous_direction = direction;
    }
}

/// Relative length error below which [`follow_the_leader`] leaves a segment alone (1e-6, far
/// inside the 0.1% the simulation promises).
pub const LENGTH_TOLERANCE: f32 = 1e-5;

/// Removes the relative velocity along every segment, root to tip:
/// `v_i ← v_i − d_i·((v_i − v_{i−1})·d_i)`, so that the velocities keep the lengths (to first
/// order) and the constraint does no work.
#[inline]
pub fn remove_stretch_velocity(positions: &[Vec3], velocities: &mut [Vec3]) {
    for i in 1..positions.len() {
        let direction = (positions[i] - positions[i - 1]).normalize_or_zero();
        let relative = velocities[i] - velocities[i - 1];
        velocities[i] -= direction * relative.dot(direction);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_restores_lengths_and_kills_stretch_velocity() {
        let mut positions = vec![
            Vec3::ZERO,
            Vec3::new(0.0, -0.013, 0.001),
            Vec3::new(0.004, -0.02, 0.0),
        ];
        let lengths = [0.0, 0.01, 0.01];
        follow_the_leader(&mut positions, &lengths);
        for i in 1..3 {
            let length = (positions[i] - positions[i - 1]).length();
            assert!((length - 0.01).abs() < 2e-8);
        }
        // The mass-weighted projection converges quadratically and keeps the centre of mass.
        let start = vec![
            Vec3::ZERO,
            Vec3::new(0.0, -0.013, 0.001),
            Vec3::new(0.004, -0.02, 0.0),
        ];
        let mut projected = start.clone();
        let masses = [1.0f32, 2.0, 0.5];
        let mut directions = vec![Vec3::ZERO; 3];
        let mut work = vec![Vec4::ZERO; 3];
        project_lengths(
            &mut projected,
            |i| 1.0 / masses[i],
            &lengths,
            &mut directions,
            &mut work,
            4,
        );
        for i in 1..3 {
            let length = (projected[i] - projected[i - 1]).length();
            assert!((length - 0.01).abs() < 1e-6, "{length}");
        }
        let centre = |p: &[Vec3]| p.iter().zip(masses).map(|(x, m)| *x * m).sum::<Vec3>();
        assert!((centre(&projected) - centre(&start)).length() < 1e-6);
        let mut velocities = vec![
            Vec3::ZERO,
            Vec3::new(0.3, -1.0, 0.2),
            Vec3::new(-0.5, 0.4, 0.1),
        ];
        remove_stretch_velocity(&positions, &mut velocities);
        for i in 1..3 {
            let d = (positions[i] - positions[i - 1]).normalize();
            assert!((velocities[i] - velocities[i - 1]).dot(d).abs() < 1e-6);
        }
    }
}
