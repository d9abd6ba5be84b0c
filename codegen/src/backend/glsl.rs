//! GLSL printer (work in progress: emits nothing yet).

use crate::builder::GeneratedFile;
use crate::plan::Plan;

/// Print every scheme of the plan as GLSL files.
pub fn write(_plan: &Plan, _command: &str) -> Vec<GeneratedFile> {
    Vec::new()
}
