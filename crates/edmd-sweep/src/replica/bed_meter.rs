//! A shaken bed sampled at uniform times (PHYSICS.md §8.4). The τ schedule samples per collision,
//! which over-weighs the moments of impact; this meter takes [`SAMPLES_PER_PERIOD`] samples per
//! floor period instead, sample k at time k·T/16 so that its floor phase is bin k mod 16. The run
//! stops at every such time from its start, so that its course does not depend on τ_max (an
//! `edmd extend` then equals a longer run), and records from the first sample point at or after
//! half of τ_max. It keeps running sums only, so a checkpoint holds it whole, and
//! [`BedMeter::summary`] turns them into the bed's profiles, spectrum and flow.
//!
//! Fourier sums are kept apart for two interleaved halves of the samples (alternate blocks of
//! [`BLOCK`]): an amplitude is read from their product, 4 Re(a b*) = |a + b|² − |a − b|², which a
//! signal steady over the run fills and noise that decorrelates within a block leaves empty on
//! average, so thin, hot beds do not read their fluctuations as waves or rolls.

use edmd_core::Vector;
use serde::{Deserialize, Serialize};

use crate::spec::Replica;

/// Samples per floor period, and so phase bins.
pub const SAMPLES_PER_PERIOD: u64 = 16;
/// A grain touches the floor when the gap under it is below this many diameters.
pub const CONTACT_GAP: f64 = 0.05;
/// The columns of the velocity field and of the undulations are about this many diameters wide.
pub const COLUMN_WIDTH: f64 = 2.0;
/// A roll pair spans at least this many columns (8 diameters): shorter modes are not searched.
pub const ROLL_COLUMNS: usize = 4;
/// Samples per block of the interleaved halves (4 floor periods).
pub const BLOCK: u64 = 4 * SAMPLES_PER_PERIOD;

/// A Fourier sum [re, im] per half.
type Halves = [[f64; 2]; 2];

/// The running sums of a shaken bed's uniform-time samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BedMeter {
    amplitude: f64,
    omega: f64,
    diameter: f64,
    dim: usize,
    z_width: f64,
    x_width: f64,
    z_bins: usize,
    x_bins: usize,
    /// The index of the next sample time, k·T/16.
    next: u64,
    /// Whether the sample times are recorded (from the window's start on) or only stopped at.
    recording: bool,
    samples: u64,
    /// Per phase bin and height bin: grains, Σ m, Σ m v (D components), Σ m |v|².
    moments: Vec<f64>,
    /// Per height bin and column: grains, and Σ v_z per half.
    cells: Vec<f64>,
    flux: [Vec<f64>; 2],
    /// Σ of the centre of mass's height, and its Fourier sums at f and f/2.
    com: f64,
    com_f: Halves,
    com_half: Halves,
    /// Per column: the Fourier sum at f/2 of its mean height less the bed's.
    columns_half: Vec<Halves>,
    /// Samples with a grain touching the floor, and Σ of the grains touching.
    touched: u64,
    touching: f64,
}

impl BedMeter {
    /// A meter for shaken replica `r` at time `time`, its height in `z_bins` bins (those of the
    /// density profile); it stops at sample times from the first after `time` on, and records
    /// once started.
    pub fn new(r: &Replica, z_bins: usize, time: f64) -> Self {
        let sides = r.sides();
        let (amplitude, omega) = r.floor_motion();
        let diameter = r.largest_diameter();
        let x_bins = ((sides[0] / (COLUMN_WIDTH * diameter)) as usize).max(1);
        let z_bins = z_bins.max(1);
        let interval = std::f64::consts::TAU / omega / SAMPLES_PER_PERIOD as f64;
        BedMeter {
            amplitude,
            omega,
            diameter,
            dim: r.dim,
            z_width: sides[r.dim - 1] / z_bins as f64,
            x_width: sides[0] / x_bins as f64,
            z_bins,
            x_bins,
            next: (time / interval).floor() as u64 + 1,
            recording: false,
            samples: 0,
            moments: vec![0.0; SAMPLES_PER_PERIOD as usize * z_bins * (3 + r.dim)],
            cells: vec![0.0; z_bins * x_bins],
            flux: [vec![0.0; z_bins * x_bins], vec![0.0; z_bins * x_bins]],
            com: 0.0,
            com_f: [[0.0; 2]; 2],
            com_half: [[0.0; 2]; 2],
            columns_half: vec![[[0.0; 2]; 2]; x_bins],
            touched: 0,
            touching: 0.0,
        }
    }

    fn interval(&self) -> f64 {
        std::f64::consts::TAU / self.omega / SAMPLES_PER_PERIOD as f64
    }

    /// Records from the next sample time on (no-op once started).
    pub fn start(&mut self) {
        self.recording = true;
    }

    /// Whether the sample times are recorded.
    pub fn recording(&self) -> bool {
        self.recording
    }

    /// Forgets every sample and stops recording, keeping the sample times (for a run that goes on
    /// under a longer τ_max, whose window starts later).
    pub fn restart(&mut self) {
        self.recording = false;
        self.samples = 0;
        self.moments.fill(0.0);
        self.cells.fill(0.0);
        self.flux.iter_mut().for_each(|f| f.fill(0.0));
        (self.com, self.com_f, self.com_half) = (0.0, [[0.0; 2]; 2], [[0.0; 2]; 2]);
        self.columns_half.fill([[0.0; 2]; 2]);
        (self.touched, self.touching) = (0, 0.0);
    }

    /// The next sample time.
    pub fn next_time(&self) -> f64 {
        self.next as f64 * self.interval()
    }

    /// Passes the sample time due now without recording it (before the window).
    pub fn skip(&mut self) {
        self.next += 1;
    }

    /// Samples taken.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Records the sample due now: the grains' positions, velocities, masses and radii.
    pub fn record<const D: usize>(
        &mut self,
        x: &[Vector<D>],
        v: &[Vector<D>],
        m: &[f64],
        radius: &[f64],
    ) {
        debug_assert!(self.recording, "samples are recorded after the start");
        let k = self.next;
        self.next += 1;
        self.samples += 1;
        let phase = (k % SAMPLES_PER_PERIOD) as usize;
        let h = ((k / BLOCK) % 2) as usize;
        let angle = std::f64::consts::TAU * phase as f64 / SAMPLES_PER_PERIOD as f64;
        let half = std::f64::consts::PI * (k % (2 * SAMPLES_PER_PERIOD)) as f64
            / SAMPLES_PER_PERIOD as f64;
        let floor = self.amplitude * (1.0 - angle.cos());
        let mut columns = vec![(0.0, 0.0); self.x_bins];
        let (mut height, mut touching) = (0.0, 0.0);
        for i in 0..x.len() {
            let (z, vz) = (x[i][D - 1], v[i][D - 1]);
            let zb = ((z / self.z_width) as usize).min(self.z_bins - 1);
            let xb = ((x[i][0] / self.x_width) as usize).min(self.x_bins - 1);
            self.add_moments(phase, zb, m[i], &v[i]);
            self.cells[zb * self.x_bins + xb] += 1.0;
            self.flux[h][zb * self.x_bins + xb] += vz;
            columns[xb].0 += 1.0;
            columns[xb].1 += z;
            height += z;
            if z - radius[i] - floor < CONTACT_GAP * self.diameter {
                touching += 1.0;
            }
        }
        let height = height / x.len() as f64;
        add_fourier(&mut self.com_f[h], height, angle);
        add_fourier(&mut self.com_half[h], height, half);
        self.com += height;
        for (sum, &(grains, z)) in self.columns_half.iter_mut().zip(&columns) {
            let column = if grains > 0.0 { z / grains } else { height };
            add_fourier(&mut sum[h], column - height, half);
        }
        self.touched += u64::from(touching > 0.0);
        self.touching += touching;
    }

    fn add_moments<const D: usize>(&mut self, phase: usize, zb: usize, m: f64, v: &Vector<D>) {
        let stride = 3 + D;
        let at = (phase * self.z_bins + zb) * stride;
        let slot = &mut self.moments[at..at + stride];
        slot[0] += 1.0;
        slot[1] += m;
        for a in 0..D {
            slot[2 + a] += m * v[a];
        }
        slot[2 + D] += m * v.norm_squared();
    }
}

/// Adds x e^{−iθ} to a Fourier sum [re, im].
fn add_fourier(sum: &mut [f64; 2], x: f64, theta: f64) {
    let (s, c) = theta.sin_cos();
    sum[0] += x * c;
    sum[1] -= x * s;
}

/// What a shaken bed's uniform-time samples show (PHYSICS.md §8.4); lengths in diameters, speeds
/// in √(g d).
#[derive(Debug, Clone, PartialEq)]
pub struct BedSummary {
    /// Samples averaged over.
    pub samples: u64,
    /// The bins' centres in height.
    pub height: Vec<f64>,
    /// The packing fraction per height bin, time-averaged.
    pub packing: Vec<f64>,
    /// The packing fraction per floor phase bin and height bin, [16][z] flattened.
    pub phase_packing: Vec<f64>,
    /// The granular temperature per height bin, from velocities less their mean at the same phase
    /// and height (NaN where no grain was seen).
    pub temperature: Vec<f64>,
    /// The time-averaged vertical velocity per height bin and column, [z][x] flattened (NaN where
    /// no grain was seen).
    pub vertical_velocity: Vec<f64>,
    /// Columns of the velocity field.
    pub columns: usize,
    /// The centre of mass's mean height.
    pub com_mean: f64,
    /// The centre of mass's amplitude at the floor's frequency f.
    pub com_f: f64,
    /// The centre of mass's amplitude at f/2 (period doubling).
    pub com_half_f: f64,
    /// The rms over columns of the amplitude at f/2 of a column's height less the bed's.
    pub undulation: f64,
    /// The largest horizontal Fourier amplitude of the time-averaged vertical velocity, averaged
    /// over height with the grains as weights.
    pub convection: f64,
    /// The mode of [`Self::convection`]: roll pairs across the box.
    pub convection_mode: usize,
    /// The same rms of the halves' difference at that mode: the noise [`Self::convection`] was
    /// cleared of.
    pub convection_noise: f64,
    /// The fraction of samples in which a grain touches the floor.
    pub contact_fraction: f64,
    /// The grains touching the floor, on average.
    pub touching: f64,
}

impl BedMeter {
    /// The bed's profiles, spectrum and flow from the samples so far (None before the first).
    pub fn summary(&self, r: &Replica) -> Option<BedSummary> {
        if self.samples == 0 {
            return None;
        }
        let k = self.samples as f64;
        let d = self.diameter;
        let stride = 3 + self.dim;
        let phases = SAMPLES_PER_PERIOD as usize;
        let sides = r.sides();
        let layer = sides[..self.dim - 1].iter().product::<f64>() * self.z_width;
        // Packing per grain seen in a bin per sample: its mean volume over the bin's volume.
        let grain = r.grain_volume() / r.n as f64 / layer;
        let at = |p: usize, z: usize, s: usize| self.moments[(p * self.z_bins + z) * stride + s];
        let per_phase = k / phases as f64;
        let phase_packing = (0..phases)
            .flat_map(|p| (0..self.z_bins).map(move |z| (p, z)))
            .map(|(p, z)| at(p, z, 0) * grain / per_phase)
            .collect();
        let packing = (0..self.z_bins)
            .map(|z| (0..phases).map(|p| at(p, z, 0)).sum::<f64>() * grain / k)
            .collect();
        let temperature = (0..self.z_bins)
            .map(|z| {
                let (mut heat, mut grains) = (0.0, 0.0);
                for p in 0..phases {
                    let (n, mass) = (at(p, z, 0), at(p, z, 1));
                    if n > 0.0 {
                        let momentum2: f64 = (0..self.dim).map(|a| at(p, z, 2 + a).powi(2)).sum();
                        heat += at(p, z, 2 + self.dim) - momentum2 / mass;
                        grains += n;
                    }
                }
                heat / (self.dim as f64 * grains)
            })
            .collect();
        let speed = (r.gravity * d).sqrt();
        let vertical_velocity = (0..self.cells.len())
            .map(|c| match self.cells[c] {
                n if n > 0.0 => (self.flux[0][c] + self.flux[1][c]) / n / speed,
                _ => f64::NAN,
            })
            .collect();
        let (convection, convection_mode, convection_noise) = self.convection(speed);
        let undulation = (self.columns_half.iter().map(shared).sum::<f64>() / self.x_bins as f64)
            .max(0.0)
            .sqrt();
        Some(BedSummary {
            samples: self.samples,
            height: (0..self.z_bins)
                .map(|z| (z as f64 + 0.5) * self.z_width)
                .collect(),
            packing,
            phase_packing,
            temperature,
            vertical_velocity,
            columns: self.x_bins,
            com_mean: self.com / k / d,
            com_f: 2.0 * shared(&self.com_f).max(0.0).sqrt() / k / d,
            com_half_f: 2.0 * shared(&self.com_half).max(0.0).sqrt() / k / d,
            undulation: 2.0 * undulation / k / d,
            convection,
            convection_mode,
            convection_noise,
            contact_fraction: self.touched as f64 / k,
            touching: self.touching / k,
        })
    }

    /// The largest horizontal mode of the time-averaged vertical velocity, among wavelengths of at
    /// least [`ROLL_COLUMNS`] columns: per height bin the amplitude 2|Σ_x Σv_z e^{−2πimx/L}| / Σ_x
    /// grains (squared from the halves' product), its rms over height weighted by the grains; in
    /// `speed`, with its mode m and the rms of the halves' difference (the noise) at that mode.
    fn convection(&self, speed: f64) -> (f64, usize, f64) {
        let j = self.x_bins;
        let mut best = (0.0, 0, 0.0);
        for m in 1..=(j / ROLL_COLUMNS) {
            let (mut sum, mut noise, mut weight) = (0.0, 0.0, 0.0);
            for z in 0..self.z_bins {
                let row = z * j..(z + 1) * j;
                let grains: f64 = self.cells[row.clone()].iter().sum();
                if grains == 0.0 {
                    continue;
                }
                let mut mode = [[0.0; 2]; 2];
                for (h, flux) in self.flux.iter().enumerate() {
                    for (x, f) in flux[row.clone()].iter().enumerate() {
                        let theta = std::f64::consts::TAU * (m * x) as f64 / j as f64;
                        add_fourier(&mut mode[h], *f, theta);
                    }
                }
                sum += 4.0 * shared(&mode) / grains;
                noise += 4.0 * apart(&mode) / grains;
                weight += grains;
            }
            let rms = (sum / weight).max(0.0).sqrt() / speed;
            if rms > best.0 || m == 1 {
                best = (rms, m, (noise / weight).sqrt() / speed);
            }
        }
        best
    }
}

/// |a + b|² − |a − b|² = 4 Re(a b*) of a sum's two halves: the power of what both halves share
/// (negative where noise outweighs it; totals are floored at 0).
fn shared(s: &Halves) -> f64 {
    4.0 * (s[0][0] * s[1][0] + s[0][1] * s[1][1])
}

/// |a − b|² of a sum's two halves: the power of what differs between them.
fn apart(s: &Halves) -> f64 {
    (s[0][0] - s[1][0]).powi(2) + (s[0][1] - s[1][1]).powi(2)
}
