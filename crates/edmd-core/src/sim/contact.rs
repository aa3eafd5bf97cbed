//! Contacts: the pair collision (normal impulse, rough tangential part, random rotation) and the wall.

use nalgebra::Vector3;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::shear::PairChange;
use super::Simulation;
use crate::calendar::Calendar;
use crate::predict::approaching;
use crate::{Boundary, CollisionRule, Vector};

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Applies the collision rule to the touching pair `(i, j)`.
    #[inline]
    pub(super) fn collide(&mut self, i: usize, j: usize) {
        let (pi, pj) = (self.particles[i], self.particles[j]);
        let now = self.now;
        let (pos_i, pos_j) = (pi.at(now), pj.at(now));
        // The image of j nearest to i, and the separation written exactly as `search` writes it, so
        // that the approach test below and the prediction agree to the last bit: a pair found
        // approaching is treated as approaching, and one found receding is never predicted again.
        let (ri, vi_img) = self.pair_image(&pos_i, &pi.vel, &pos_j);
        let dr = ri - pj.at(now);
        let dv = vi_img - pj.vel;
        let b = dr.dot(&dv);
        if !approaching(
            b,
            dr.norm_squared(),
            pi.vel.norm_squared() + pj.vel.norm_squared(),
        ) {
            // Round-off turned a grazing contact into a separation: nothing to exchange.
            return;
        }
        let dist = dr.norm();
        let normal = dr / dist;
        let gn = b / dist;
        let (mi, mj) = (self.meta[i].mass, self.meta[j].mass);
        let m_eff = mi * mj / (mi + mj);
        let r_eff = pi.radius * pj.radius / (pi.radius + pj.radius);
        let t_phys = self.time();
        let (si, sj) = if i < j {
            let (lo, hi) = self.rule_state.split_at_mut(j);
            (&mut lo[i], &mut hi[0])
        } else {
            let (lo, hi) = self.rule_state.split_at_mut(i);
            (&mut hi[0], &mut lo[j])
        };
        let eps = self
            .rule
            .restitution_at(-gn * self.inv_scale, m_eff, r_eff, t_phys, si, sj);
        let impulse = -(1.0 + eps) * gn * m_eff;
        // New velocities, and the trajectories' origins moved so that positions stay put at `now`.
        let (mut vi, mut vj) = (
            pi.vel + normal * (impulse / mi),
            pj.vel - normal * (impulse / mj),
        );
        // The rotational energy the contact removes (for the sheared sums).
        let mut spin_loss = 0.0;
        if R::ROUGH {
            let (beta, q) = self.rule.roughness();
            let (wi, wj) = (Vector3::from(R::spin(si)), Vector3::from(R::spin(sj)));
            let kick = RoughKick::new(beta, q, (mi, mj), (pi.radius, pj.radius), &normal, &dv);
            let (pt, dwi, dwj) = kick.apply(wi, wj);
            for a in 0..D {
                vi[a] += pt[a] / mi;
                vj[a] -= pt[a] / mj;
            }
            // Read by the sheared sums only; elsewhere the compiler drops it.
            let (ii, ij) = (
                q * mi * pi.radius * pi.radius,
                q * mj * pj.radius * pj.radius,
            );
            spin_loss = 0.5 * ii * (wi.norm_squared() - (wi + dwi).norm_squared())
                + 0.5 * ij * (wj.norm_squared() - (wj + dwj).norm_squared());
            R::set_spin(si, (wi + dwi).into());
            R::set_spin(sj, (wj + dwj).into());
        }
        if R::ROTATES && self.rule.rotates() {
            (vi, vj) = self.rotate_pair(vi, vj, vi_img - pi.vel, (mi, mj), &normal);
        }
        self.particles[i].set_velocity(pos_i, vi, now);
        self.particles[j].set_velocity(pos_j, vj, now);
        self.counters.pair_collisions += 1;
        // Physical momentum transfer (the simulated one carries the deep-cooling scale).
        self.counters.virial += impulse * dist * self.inv_scale;
        self.add_shear_sums(&PairChange {
            masses: (mi, mj),
            before: (pi.vel, pj.vel),
            after: (vi, vj),
            image_velocity: vi_img,
            separation: dr,
            spin_loss,
        });
    }

    /// The remedy's random rotation of the pair's new velocities `vi`, `vj`, taken in the frame of
    /// i's image: `slide` is how much faster i's image moves than i (±a L_y across a sliding face,
    /// where the lab-frame difference is not the pair's relative velocity; 0 elsewhere).
    #[inline]
    fn rotate_pair(
        &mut self,
        vi: Vector<D>,
        vj: Vector<D>,
        slide: Vector<D>,
        (mi, mj): (f64, f64),
        normal: &Vector<D>,
    ) -> (Vector<D>, Vector<D>) {
        let theta = self.rule.rotation_angle(&mut self.rng);
        match self.sliding(slide) {
            Some(slide) => {
                let (wi, wj) =
                    rotate_relative(vi + slide, vj, mi, mj, normal, theta, &mut self.rng);
                (wi - slide, wj)
            }
            None => rotate_relative(vi, vj, mi, mj, normal, theta, &mut self.rng),
        }
    }
}

/// A D-vector as a 3-vector (z = 0 in 2D).
#[inline(always)]
fn pad3<const D: usize>(v: &Vector<D>) -> Vector3<f64> {
    Vector3::from_fn(|k, _| if k < D { v[k] } else { 0.0 })
}

/// The tangential part of a rough contact (PHYSICS.md §6.5): the contact point's relative velocity
/// `g_c = g − (R_i ω_i + R_j ω_j) × n` loses the fraction `(1 + β)` of its tangential part.
#[derive(Debug, Clone, Copy)]
struct RoughKick {
    beta: f64,
    /// Moment-of-inertia factor, `I = q m R²`.
    q: f64,
    masses: (f64, f64),
    radii: (f64, f64),
    normal: Vector3<f64>,
    /// Relative velocity `v_i − v_j` of the centres.
    g: Vector3<f64>,
}

impl RoughKick {
    #[inline(always)]
    fn new<const D: usize>(
        beta: f64,
        q: f64,
        masses: (f64, f64),
        radii: (f64, f64),
        normal: &Vector<D>,
        g: &Vector<D>,
    ) -> Self {
        RoughKick {
            beta,
            q,
            masses,
            radii,
            normal: pad3(normal),
            g: pad3(g),
        }
    }

    /// The tangential impulse on `i` (`−` of it on `j`) and the two spin changes, for spins `wi`, `wj`.
    #[inline(always)]
    fn apply(
        &self,
        wi: Vector3<f64>,
        wj: Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let ((mi, mj), (ri, rj), q, n) = (self.masses, self.radii, self.q, &self.normal);
        let arm = wi * ri + wj * rj;
        let gc = self.g - arm.cross(n);
        let gt = gc - n * gc.dot(n);
        let inv_mu_t = 1.0 / mi + 1.0 / mj + 1.0 / (q * mi) + 1.0 / (q * mj);
        let pt = gt * (-(1.0 + self.beta) / inv_mu_t);
        // Torques: i is touched at −R_i n, j at +R_j n with −P_t.
        let np = n.cross(&pt);
        let (ii, ij) = (q * mi * ri * ri, q * mj * rj * rj);
        (pt, np * (-ri) / ii, np * (-rj) / ij)
    }
}

/// Rotates the relative velocity `vi − vj` by `theta` about a random axis in the centre-of-mass frame,
/// keeping the centre-of-mass velocity and |vi − vj|; the direction is flipped if the first choice
/// would make the pair approach along `normal`, and no rotation is done if both would.
fn rotate_relative<const D: usize>(
    vi: Vector<D>,
    vj: Vector<D>,
    mi: f64,
    mj: f64,
    normal: &Vector<D>,
    theta: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> (Vector<D>, Vector<D>) {
    use rand::Rng;
    let g = vi - vj;
    let speed = g.norm();
    if theta == 0.0 || speed == 0.0 {
        return (vi, vj);
    }
    let gh = g / speed;
    // A random unit vector perpendicular to g (in 2D: one of the two normals).
    let mut w = Vector::<D>::from_fn(|_, _| rng.sample::<f64, _>(rand_distr::StandardNormal));
    w -= gh * w.dot(&gh);
    let wn = w.norm();
    if wn == 0.0 {
        return (vi, vj);
    }
    w /= wn;
    let (s, c) = theta.sin_cos();
    let mut rotated = (gh * c + w * s) * speed;
    if rotated.dot(normal) < 0.0 {
        rotated = (gh * c - w * s) * speed;
        if rotated.dot(normal) < 0.0 {
            return (vi, vj);
        }
    }
    let mt = mi + mj;
    let vcm = (vi * mi + vj * mj) / mt;
    (vcm + rotated * (mj / mt), vcm - rotated * (mi / mt))
}
