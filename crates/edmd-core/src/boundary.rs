//! Scenes: which box axes are periodic and which end in hard specular walls.
//!
//! A scene is a zero-sized type; its wall mask is a const generic, so every `is_wall(axis)` test is
//! resolved at compile time and a periodic scene never evaluates a wall.

use std::fmt::Debug;

/// Boundary conditions of the box, per axis.
pub trait Boundary: Copy + Clone + Debug + Default + Send + Sync + 'static {
    /// Bit `a` set: axis `a` has hard walls at 0 and L; clear: periodic.
    const WALL_MASK: u8;
    /// Short name used in files and messages.
    const NAME: &'static str;
    /// True for scenes with uniform gravity along −(last axis) (`SimParams::gravity`); only these
    /// solve quadratics for crossings and wall contacts.
    const GRAVITY: bool = false;
    /// True for the sheared periodic scene ([`LeesEdwards`]): the images across the y faces slide
    /// along x (`SimParams::shear_rate`).
    const SHEARED: bool = false;

    /// True if axis `a` has walls.
    #[inline(always)]
    fn is_wall(a: usize) -> bool {
        Self::WALL_MASK & (1 << a) != 0
    }

    /// True if any axis has walls.
    #[inline(always)]
    fn has_walls() -> bool {
        Self::WALL_MASK != 0
    }
}

/// A scene with walls on the axes whose bits are set in `MASK` (bit 0 = x) and periodic elsewhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct Axes<const MASK: u8>;

impl<const MASK: u8> Boundary for Axes<MASK> {
    const WALL_MASK: u8 = MASK;
    const NAME: &'static str = match MASK {
        0 => "periodic",
        0b111 => "walls",
        0b110 => "channel",
        _ => "mixed",
    };
}

/// Like [`Axes`], with uniform gravity pulling towards the floor at 0 of the last axis (y in 2D,
/// z in 3D), which must have walls.
#[derive(Debug, Clone, Copy, Default)]
pub struct GravityAxes<const MASK: u8>;

impl<const MASK: u8> Boundary for GravityAxes<MASK> {
    const WALL_MASK: u8 = MASK;
    const NAME: &'static str = match MASK {
        0b111 => "container",
        0b110 => "column",
        _ => "gravity-mixed",
    };
    const GRAVITY: bool = true;
}

/// Walls on every axis and gravity: a closed container with a floor.
pub type Container = GravityAxes<0b111>;
/// Periodic in x, walls elsewhere, gravity: a column with a floor.
pub type Column = GravityAxes<0b110>;

/// Periodic on every axis.
pub type Periodic = Axes<0>;

/// Lees–Edwards ("sliding brick") boundaries: periodic on every axis, with the images across the
/// faces normal to y displaced along x by Δ(t) = a L_y t (mod L_x) and moving with ±a L_y, `a` the
/// shear rate ([`crate::SimParams::shear_rate`]): the uniform shear flow u_x = a (y − L_y/2). A grain
/// leaving through the upper y face re-enters through the lower one at x − Δ with v_x − a L_y (and
/// the reverse), so that its image is where it left (PHYSICS.md §7).
#[derive(Debug, Clone, Copy, Default)]
pub struct LeesEdwards;

impl Boundary for LeesEdwards {
    const WALL_MASK: u8 = 0;
    const NAME: &'static str = "lees-edwards";
    const SHEARED: bool = true;
}
/// Hard walls on every axis (in 2D the z bit is ignored).
pub type Walls = Axes<0b111>;
/// Periodic in x, walls on the other axes (a channel).
pub type Channel = Axes<0b110>;
