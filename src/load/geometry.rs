//! Shapes from the config: transforms composed, meshes loaded, spheres checked.

use super::check::{check, finite3};
use crate::config::{ShapeConfig, ShapeKind, TransformOp};
use crate::error::InputError;
use crate::math::Transform;
use crate::shape::{mesh_io, Disk, Mesh, Shape, Sphere};
use glam::{Mat4, Vec3};
use std::path::Path;

/// Composes a list of transform steps (the first acts first).
pub fn transform(ops: &[TransformOp], file: &Path, field: &str) -> Result<Transform, InputError> {
    let mut m = Mat4::IDENTITY;
    for (i, op) in ops.iter().enumerate() {
        let f = format!("{field}[{i}]");
        let step = match op {
            TransformOp::Matrix(rows) => {
                check(
                    rows.iter().flatten().all(|v| v.is_finite()),
                    file,
                    &f,
                    "the matrix has non-finite entries",
                )?;
                let last = rows[3];
                check(
                    last == [0.0, 0.0, 0.0, 1.0],
                    file,
                    &f,
                    format!(
                        "the matrix's last row is {last:?}, not [0, 0, 0, 1]: prism takes affine \
                         transforms only (a projective one would bend straight rays); write the \
                         last row as (0, 0, 0, 1)"
                    ),
                )?;
                Mat4::from_cols_array_2d(rows).transpose()
            }
            TransformOp::Translate(t) => {
                check(
                    finite3(*t),
                    file,
                    &f,
                    "the translation has non-finite components",
                )?;
                Mat4::from_translation(Vec3::from(*t))
            }
            TransformOp::Scale(s) => {
                check(
                    finite3(*s) && s.iter().all(|&v| v != 0.0),
                    file,
                    &f,
                    format!("scale {s:?} must be finite and non-zero"),
                )?;
                Mat4::from_scale(Vec3::from(*s))
            }
            TransformOp::Rotate { axis, angle } => {
                let a = Vec3::from(*axis);
                check(
                    finite3(*axis) && a.length() > 0.0 && angle.is_finite(),
                    file,
                    &f,
                    "the rotation needs a non-zero finite axis and a finite angle",
                )?;
                crate::math::rotation::axis_angle(a.normalize(), angle.to_radians())
            }
            TransformOp::LookAt { origin, target, up } => {
                let t = Transform::look_at((*origin).into(), (*target).into(), (*up).into()).ok_or_else(|| {
                    InputError::new(file, "look-at needs distinct origin and target and an up vector not parallel to the view direction")
                        .field(&f)
                        .hint("move the origin off the target, or give an up vector that is not along target − origin")
                })?;
                t.m
            }
        };
        m = step * m;
    }
    let t = Transform::from_matrix(m).ok_or_else(|| {
        InputError::new(
            file,
            "the transform is singular (it flattens space) or not finite",
        )
        .field(field)
        .hint("check for a zero scale or a degenerate matrix")
    })?;
    super::extent::check_transform(&t, file, field)?;
    Ok(t)
}

/// Builds shape `sc` (called `field` in errors); mesh paths are relative to `base`.
pub fn shape(
    sc: &ShapeConfig,
    file: &Path,
    field: &str,
    base: &Path,
    warnings: &mut Vec<String>,
) -> Result<Shape, InputError> {
    let t = transform(&sc.to_world, file, &format!("{field}.to_world"))?;
    let shape = match &sc.shape {
        ShapeKind::Rectangle => Shape::Mesh(Mesh::rectangle().transformed(&t, sc.flip_normals)),
        ShapeKind::Cube => Shape::Mesh(Mesh::cube().transformed(&t, sc.flip_normals)),
        ShapeKind::Disk => Shape::Disk(Disk {
            to_world: t,
            flip: sc.flip_normals,
        }),
        ShapeKind::Sphere { center, radius } => {
            // Name the value that is wrong, not its neighbour.
            check(
                finite3(*center),
                file,
                &format!("{field}.shape.center"),
                format!("a sphere needs a finite center (got {center:?})"),
            )?;
            check(
                radius.is_finite() && *radius > 0.0,
                file,
                &format!("{field}.shape.radius"),
                format!("a sphere needs a finite radius > 0 (got {radius})"),
            )?;
            let cols = [t.vector(Vec3::X), t.vector(Vec3::Y), t.vector(Vec3::Z)];
            let s = cols[0].length();
            let uniform = cols.iter().all(|c| (c.length() - s).abs() <= 1e-4 * s)
                && cols[0].dot(cols[1]).abs() <= 1e-4 * s * s
                && cols[1].dot(cols[2]).abs() <= 1e-4 * s * s
                && cols[0].dot(cols[2]).abs() <= 1e-4 * s * s;
            check(uniform, file, &format!("{field}.to_world"), "a sphere's transform may only rotate, translate and scale uniformly; use a Mesh for ellipsoids")?;
            Shape::Sphere(Sphere {
                center: t.point(Vec3::from(*center)),
                radius: radius * s,
                flip: sc.flip_normals,
            })
        }
        ShapeKind::Mesh { path } => {
            let full = base.join(path);
            let mesh = mesh_io::load(&full).map_err(|m| {
                let err = InputError::new(file, m)
                    .field(format!("{field}.shape.path"))
                    .hint("give an OBJ or PLY mesh prism reads (scenes/README.md)");
                let hint = "mesh paths are relative to the scene file";
                super::inputs::missing_hint(err, &full, hint)
            })?;
            Shape::Mesh(mesh.transformed(&t, sc.flip_normals))
        }
        ShapeKind::Gltf { .. } => unreachable!("glTF shapes are expanded by load::gltf"),
    };
    if let Shape::Mesh(m) = &shape {
        let degenerate = (0..m.indices.len())
            .filter(|&k| shape.prim_is_degenerate(k))
            .count();
        if degenerate == m.indices.len() {
            // An area that overflows f32 (coordinates past ~1e19) is not zero: say which.
            let big = m
                .positions
                .iter()
                .map(|p| p.abs().max_element())
                .fold(0.0, f32::max);
            let (message, hint) = if big > 1e18 {
                (format!("the coordinates are too large (up to {big:e}, after its transform): the triangles' areas overflow single precision"), "scale the mesh down (its units are the scene's)")
            } else {
                (
                    "every triangle of this shape has zero area (after its transform)".into(),
                    "check the vertices and the transform's scale",
                )
            };
            return Err(InputError::new(file, message).field(field).hint(hint));
        }
        if degenerate > 0 {
            warnings.push(format!(
                "{}: {field}: {degenerate} of {} triangles have zero area and are skipped",
                file.display(),
                m.indices.len()
            ));
        }
    }
    Ok(shape)
}
