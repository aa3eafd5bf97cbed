pub use edmd_core::*;
