//! Outputs of a run: `curves.csv` (tidy), the figures (PNG + SVG), `report.html` (self-contained)
//! and the cylinder's VTK fields, all written atomically through [`atomic::Staging`].

pub mod atomic;
pub mod base64;
pub mod csv;
pub mod figures;
pub mod plot;
pub mod report;

pub use atomic::{OutputError, Staging};
