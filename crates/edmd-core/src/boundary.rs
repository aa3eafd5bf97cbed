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

/// Periodic on every axis.
pub type Periodic = Axes<0>;
/// Hard walls on every axis (in 2D the z bit is ignored).
pub type Walls = Axes<0b111>;
/// Periodic in x, walls on the other axes (a channel).
pub type Channel = Axes<0b110>;
