//! A library user's program: reads a glTF's alpha-tested primitives and
//! bakes them into opacity-micromap API buffers with `bake::mesh`
//! (`cargo run -p micromap-index-assets --example bake_gltf -- SCENE.gltf`).

use micromap_index::bake::mesh::{bake_meshes, Mesh, MeshOptions, MeshTriangles};
use micromap_index_assets::{read_gltf_file, AlphaImage, Limits};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let default = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/crytek-sponza/cards.gltf"
    );
    let path = std::env::args().nth(1).unwrap_or_else(|| default.into());
    let asset = read_gltf_file(path.as_ref(), &Limits::default())?;
    // The decoded images, viewed as the baker's textures (no copy).
    let textures: Vec<_> = asset
        .images
        .iter()
        .map(AlphaImage::texture)
        .collect::<Result<_, _>>()?;
    // One mesh per MASK primitive: its UVs, its texture, its material.
    let meshes: Vec<Mesh<'_>> = (asset.primitives.iter())
        .map(|p| Mesh {
            triangles: MeshTriangles::Uv(&p.triangles),
            texture: &textures[p.image],
            material: p.material(),
            vertex_alpha: p.vertex_alpha.as_deref(),
        })
        .collect();
    let baked = bake_meshes(&meshes, &MeshOptions::default(), &mut |_, _| {})?;
    // What a renderer uploads: baked.buffers.data(), .records_le_bytes(),
    // and per primitive .index_bytes(g, IndexWidth::U32).
    let report = &baked.report;
    println!(
        "{} triangles, levels {:?}, known fraction {:.4}, {} micromaps in {} bytes",
        report.triangles,
        report.levels,
        report.known_fraction,
        report.micromaps,
        baked.buffers.data().len()
    );
    Ok(())
}
