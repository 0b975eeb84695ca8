//! Reading meshes from OBJ (tobj, `obj`) and PLY (ply-rs-bw, `ply`) files. Errors are plain
//! messages; the scene loader adds the scene file and field they belong to.

use super::mesh::Mesh;
use std::path::Path;

#[path = "mesh_obj.rs"]
mod obj;
#[path = "mesh_ply.rs"]
mod ply;

/// Loads an OBJ or PLY file by its extension.
pub fn load(path: &Path) -> Result<Mesh, String> {
    crate::io::inputs::record(path);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !path.exists() {
        return Err(format!("mesh file `{}` does not exist", path.display()));
    }
    let mesh = match ext.as_deref() {
        Some("obj") => obj::load_obj(path)?,
        Some("ply") => ply::load_ply(path)?,
        _ => {
            return Err(format!(
                "`{}` is neither .obj nor .ply (the mesh formats prism reads)",
                path.display()
            ))
        }
    };
    mesh.validate()
        .map_err(|m| format!("`{}`: {m}", path.display()))?;
    Ok(mesh)
}

#[cfg(test)]
#[path = "mesh_io_tests.rs"]
mod tests;
