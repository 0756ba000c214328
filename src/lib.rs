//! activemuscle: mechanics of active skeletal muscle (see README.md).
pub mod error;
pub use error::{Error, Result};
