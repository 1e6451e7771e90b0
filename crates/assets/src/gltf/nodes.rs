//! The node tree of the default scene (glTF 2.0 "Nodes and Hierarchy"):
//! for each mesh, the world transforms of the nodes that instance it, for
//! renderers ([`MaskPrimitive::instances`](super::MaskPrimitive::instances)).
//! A node's local transform is its `matrix` (column-major) or the product
//! of `translation`, `rotation` (the quaternion normalised, `trs`) and
//! `scale`;
//! world transforms are composed from the roots down in binary64 and
//! rounded once to binary32. A node with `EXT_mesh_gpu_instancing`
//! (`instancing`) places its mesh once per instance instead, at the
//! node's world transform times the instance's. Bakes do not depend on
//! this: a malformed tree is a reason, not an error.

use super::json::Obj;
use serde_json::Value;

/// A row-major 3x4 affine transform (the last row is `0 0 0 1`).
pub(super) type Affine = [f64; 12];

/// A node's instance transforms (`EXT_mesh_gpu_instancing`), `None`
/// without them, or why they are refused.
pub(super) type InstanceTransforms = Result<Option<Vec<Affine>>, String>;

/// The identity transform, row-major 3x4 in binary32
/// ([`MaskPrimitive::instances`](super::MaskPrimitive::instances) of an
/// asset without nodes).
pub const IDENTITY_TRANSFORM: [f32; 12] =
    [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

const IDENTITY64: Affine = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// `a * b`.
fn compose(a: &Affine, b: &Affine) -> Affine {
    let mut out = [0.0; 12];
    for r in 0..3 {
        for c in 0..4 {
            let mut v = a[4 * r] * b[c] + a[4 * r + 1] * b[4 + c] + a[4 * r + 2] * b[8 + c];
            if c == 3 {
                v += a[4 * r + 3];
            }
            out[4 * r + c] = v;
        }
    }
    out
}

/// A reader's error as the reason a tree is not applied.
fn error(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// `count` finite numbers at `node[key]`, or `None` when absent.
fn numbers(node: &Obj<'_>, key: &str, count: usize) -> Result<Option<Vec<f64>>, String> {
    let Some(value) = node.map.get(key) else {
        return Ok(None);
    };
    let bad = || format!("{}: expected {count} finite numbers", node.field(key));
    let Value::Array(items) = value else {
        return Err(bad());
    };
    if items.len() != count {
        return Err(bad());
    }
    items
        .iter()
        .map(|v| v.as_f64().filter(|x| x.is_finite()).ok_or_else(bad))
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// A node's local transform.
fn local(node: &Obj<'_>) -> Result<Affine, String> {
    if let Some(m) = numbers(node, "matrix", 16)? {
        // Column-major 4x4: element (row r, column c) is m[4c + r].
        let mut out = [0.0; 12];
        for r in 0..3 {
            for c in 0..4 {
                out[4 * r + c] = m[4 * c + r];
            }
        }
        return Ok(out);
    }
    let t = numbers(node, "translation", 3)?.unwrap_or_else(|| vec![0.0; 3]);
    let q = numbers(node, "rotation", 4)?.unwrap_or_else(|| vec![0.0, 0.0, 0.0, 1.0]);
    let s = numbers(node, "scale", 3)?.unwrap_or_else(|| vec![1.0; 3]);
    trs(
        [t[0], t[1], t[2]],
        [q[0], q[1], q[2], q[3]],
        [s[0], s[1], s[2]],
    )
    .ok_or_else(|| {
        format!(
            "{}: a zero quaternion (or one whose squared norm overflows)",
            node.field("rotation")
        )
    })
}

/// `translation * rotation * scale` in binary64, the quaternion `x, y, z,
/// w` normalised: each rotation entry is a quadratic form of the stored
/// quaternion divided by its squared norm (`(w² + x² - y² - z²) / n²`,
/// `2 (x y - z w) / n²`, ...), one division each and no square root, so a
/// quarter turn such as `(0, 0, c, c)` gives exact zeros and ones. `None`
/// for a zero (or not finite) quaternion.
pub(super) fn trs(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> Option<Affine> {
    let [x, y, z, w] = q;
    let n2 = x * x + y * y + z * z + w * w;
    if !(n2.is_finite() && n2 > 0.0) {
        return None;
    }
    let rot = [
        [
            (w * w + x * x - y * y - z * z) / n2,
            2.0 * (x * y - z * w) / n2,
            2.0 * (x * z + y * w) / n2,
        ],
        [
            2.0 * (x * y + z * w) / n2,
            (w * w - x * x + y * y - z * z) / n2,
            2.0 * (y * z - x * w) / n2,
        ],
        [
            2.0 * (x * z - y * w) / n2,
            2.0 * (y * z + x * w) / n2,
            (w * w - x * x - y * y + z * z) / n2,
        ],
    ];
    let mut out = [0.0; 12];
    for r in 0..3 {
        for c in 0..3 {
            out[4 * r + c] = rot[r][c] * s[c];
        }
        out[4 * r + 3] = t[r];
    }
    Some(out)
}

/// For each of `meshes` meshes, the binary32 world transforms of the
/// default scene's nodes that instance it, in depth-first order from the
/// scene's roots; `None` when the asset has no `nodes` (every mesh then
/// counts once, in its own space). The default scene is `scene`, else
/// `scenes[0]`; without `scenes`, every node that is no other node's child
/// is a root. `instancing` gives the instance transforms of a node with a
/// mesh (`EXT_mesh_gpu_instancing`), or `None` for a node without them: a
/// node with them places its mesh once per instance, at `world * instance`
/// (composed in binary64, rounded once), and never at `world` alone.
/// Refused (with the reason): a node reached twice (a cycle or two
/// parents), an index out of range, a transform that is not finite, and
/// whatever `instancing` refuses.
pub(super) fn mesh_instances<'a>(
    root: &Obj<'a>,
    meshes: usize,
    instancing: &mut dyn FnMut(&Obj<'a>) -> InstanceTransforms,
) -> Result<Option<Vec<Vec<[f32; 12]>>>, String> {
    let nodes = root.opt_array("nodes").map_err(error)?.unwrap_or_default();
    if nodes.is_empty() {
        return Ok(None);
    }
    let node = |i: usize, what: &str| root.element("nodes", i, what).map_err(error);
    let children = |n: &Obj<'_>| -> Result<Vec<usize>, String> {
        let items = n.opt_array("children").map_err(error)?.unwrap_or_default();
        items
            .iter()
            .map(|v| {
                v.as_u64()
                    .and_then(|c| usize::try_from(c).ok())
                    .ok_or_else(|| format!("{}: expected node indices", n.field("children")))
            })
            .collect()
    };
    let scenes = root.opt_array("scenes").map_err(error)?.unwrap_or_default();
    let roots: Vec<usize> = if scenes.is_empty() {
        let mut is_child = vec![false; nodes.len()];
        for i in 0..nodes.len() {
            for c in children(&node(i, "nodes")?)? {
                if let Some(flag) = is_child.get_mut(c) {
                    *flag = true;
                }
            }
        }
        (0..nodes.len()).filter(|&i| !is_child[i]).collect()
    } else {
        let s = root.opt_usize("scene").map_err(error)?.unwrap_or(0);
        let scene = root.element("scenes", s, "scene").map_err(error)?;
        let items = scene.opt_array("nodes").map_err(error)?.unwrap_or_default();
        items
            .iter()
            .map(|v| {
                v.as_u64()
                    .and_then(|c| usize::try_from(c).ok())
                    .ok_or_else(|| format!("{}: expected node indices", scene.field("nodes")))
            })
            .collect::<Result<_, _>>()?
    };
    let mut instances = vec![Vec::new(); meshes];
    let mut seen = vec![false; nodes.len()];
    // Depth first, children in order: a stack of (node, parent's world).
    let mut stack: Vec<(usize, Affine)> = roots.iter().rev().map(|&r| (r, IDENTITY64)).collect();
    while let Some((i, parent)) = stack.pop() {
        let n = node(i, "a node's children or a scene's nodes")?;
        if std::mem::replace(&mut seen[i], true) {
            return Err(format!(
                "nodes[{i}] is reached twice (a cycle, or two parents)"
            ));
        }
        let world = compose(&parent, &local(&n)?);
        if let Some(m) = n.opt_usize("mesh").map_err(error)? {
            let placed = instances
                .get_mut(m)
                .ok_or_else(|| format!("{}: meshes[{m}] does not exist", n.field("mesh")))?;
            let round = |transform: &Affine| {
                Some(transform.map(|x| x as f32)).filter(|t| t.iter().all(|x| x.is_finite()))
            };
            match instancing(&n)? {
                None => placed.push(round(&world).ok_or_else(|| {
                    format!("nodes[{i}]: its world transform is not finite in binary32")
                })?),
                Some(locals) => {
                    placed.try_reserve(locals.len()).map_err(|_| {
                        format!(
                            "nodes[{i}]: {} instances do not fit in memory",
                            locals.len()
                        )
                    })?;
                    for (k, local) in locals.iter().enumerate() {
                        placed.push(round(&compose(&world, local)).ok_or_else(|| {
                            format!(
                                "nodes[{i}]: instance {k}'s world transform is not finite in binary32"
                            )
                        })?);
                    }
                }
            }
        }
        for c in children(&n)?.into_iter().rev() {
            stack.push((c, world));
        }
    }
    Ok(Some(instances))
}
