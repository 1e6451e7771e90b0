//! `Camera::fitting` frames what it is given: every vertex projects inside
//! the picture (within its middle 95%), the picture is filled along at
//! least one axis, and plants lying on the ground are seen from higher up
//! than cards standing up. No device needed.

use micromap_index_render::Camera;
use micromap_index_test_support::SplitMix64;

/// The normalised picture coordinates `(x, y)` in `[-1, 1]` of `p` as the
/// shaders' primary rays see it (forward, right = forward x (0, 1, 0), up =
/// right x forward; the vertical field of view; `aspect` width over height).
fn project(camera: &Camera, aspect: f64, p: [f32; 3]) -> [f64; 2] {
    let e = camera.eye.map(f64::from);
    let t = camera.target.map(f64::from);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let unit = |a: [f64; 3]| {
        let n = dot(a, a).sqrt();
        a.map(|x| x / n)
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let forward = unit(sub(t, e));
    let right = unit(cross(forward, [0.0, 1.0, 0.0]));
    let up = cross(right, forward);
    let half = (0.5 * f64::from(camera.fov_y_degrees).to_radians()).tan();
    let d = sub(p.map(f64::from), e);
    let z = dot(d, forward);
    assert!(z > 0.0, "{p:?} is behind the eye");
    [dot(d, right) / (z * half * aspect), dot(d, up) / (z * half)]
}

/// A uniform value in `[0, 1)`.
fn unit(rng: &mut SplitMix64) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn random_triangles(rng: &mut SplitMix64, n: usize, scale: [f32; 3]) -> Vec<[[f32; 3]; 3]> {
    (0..n)
        .map(|_| [0, 1, 2].map(|_| [0, 1, 2].map(|k| (unit(rng) as f32 - 0.5) * scale[k] + 3.0)))
        .collect()
}

#[test]
fn every_vertex_projects_inside_the_picture_and_the_picture_is_filled() {
    let mut rng = SplitMix64::new(35);
    for case in 0..60 {
        let scale = [0, 1, 2].map(|_| 0.01 + 10.0 * unit(&mut rng) as f32);
        let triangles = random_triangles(&mut rng, 1 + case % 7 * 20, scale);
        let aspect = [1.0f32, 16.0 / 9.0, 0.5, 3.0][case % 4];
        let camera = Camera::fitting(&triangles, aspect).unwrap();
        let mut widest = [0.0f64; 2];
        for p in triangles.iter().flatten() {
            let [x, y] = project(&camera, f64::from(aspect), *p);
            assert!(
                x.abs() <= 0.95 + 1e-5 && y.abs() <= 0.95 + 1e-5,
                "case {case}: {x} {y}"
            );
            widest = [widest[0].max(x.abs()), widest[1].max(y.abs())];
        }
        // Fitted, not merely inside: the points reach the frame's edge
        // along one axis (up to the perspective's asymmetry).
        assert!(widest[0].max(widest[1]) > 0.6, "case {case}: {widest:?}");
    }
}

#[test]
fn plants_on_the_ground_are_seen_from_higher_up_than_cards() {
    let mut rng = SplitMix64::new(7);
    let steepness = |triangles: &[[[f32; 3]; 3]]| {
        let c = Camera::fitting(triangles, 1.0).unwrap();
        let d = [0, 1, 2].map(|i| c.eye[i] - c.target[i]);
        d[1] / (d[0] * d[0] + d[2] * d[2]).sqrt()
    };
    // Flat on the ground (x, z) and standing up (x, y).
    let ground = random_triangles(&mut rng, 50, [4.0, 0.02, 4.0]);
    let cards = random_triangles(&mut rng, 50, [4.0, 4.0, 0.02]);
    assert!(steepness(&ground) > 2.0 * steepness(&cards));
    assert!(Camera::fitting(&[], 1.0).is_none());
    assert!(Camera::fitting(&[[[f32::NAN; 3]; 3]], 1.0).is_none());
}
