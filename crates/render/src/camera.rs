//! The pinhole [`Camera`]: where the primary rays start and where they
//! look, and the push-constant basis the shaders turn into one ray per
//! pixel.

use crate::error::RenderError;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where the rays start.
    pub eye: [f32; 3],
    /// The point at the picture's centre.
    pub target: [f32; 3],
    /// The vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

impl Camera {
    /// A camera that frames the box `[min, max]` in a picture of `aspect`
    /// (width over height): looking down `-z` and slightly down from above,
    /// 40 degrees vertically, at a distance that shows the box's `x` and
    /// `y` extents with a 10% margin.
    #[must_use]
    pub fn framing(bounds: [[f32; 3]; 2], aspect: f32) -> Camera {
        let [min, max] = bounds;
        let centre = [0, 1, 2].map(|i| 0.5 * (min[i] + max[i]));
        let half = [0, 1, 2].map(|i| (0.5 * (max[i] - min[i])).max(1e-3));
        let fov: f32 = 40.0;
        let t = (0.5 * fov.to_radians()).tan();
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let distance = 1.1 * (half[0] / (t * aspect)).max(half[1] / t) + half[2];
        let dir = [0.0f32, 0.35, 1.0];
        let norm = dir.iter().map(|d| d * d).sum::<f32>().sqrt();
        Camera {
            eye: [0, 1, 2].map(|i| centre[i] + distance * dir[i] / norm),
            target: centre,
            fov_y_degrees: fov,
        }
    }

    /// A camera that fits `triangles` (world space): looking along `-z`
    /// from above at the elevation (about 19, 45 or 70 degrees) under which
    /// their projections cover the most of the picture, 40 degrees
    /// vertically, placed so that every vertex's projection lies within the
    /// middle 95% of a picture of `aspect` (width over height), centred on
    /// their projections' box: the triangles fill the frame, so few rays
    /// miss the scene (cards stood up face the camera low; a plant on the
    /// ground is seen from higher up). `None` without a finite vertex.
    #[must_use]
    pub fn fitting(triangles: &[[[f32; 3]; 3]], aspect: f32) -> Option<Camera> {
        let points: Vec<[f64; 3]> = triangles
            .iter()
            .flatten()
            .filter(|p| p.iter().all(|x| x.is_finite()))
            .map(|p| p.map(f64::from))
            .collect();
        points.first()?;
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            f64::from(aspect)
        } else {
            1.0
        };
        // Elevations by their slope: the first is `framing`'s.
        let mut best: Option<(f64, Camera)> = None;
        for slope in [0.35f64, 1.0, 2.75] {
            let camera = fit_along(&points, slope, aspect);
            let covered = coverage(&camera, triangles, aspect);
            if best.as_ref().map_or(true, |(c, _)| covered > *c * 1.25) {
                best = Some((covered, camera));
            }
        }
        best.map(|(_, camera)| camera)
    }

    /// The push-constant vectors: eye, forward, right and up, the last two
    /// scaled to half the picture at distance 1.
    pub(crate) fn basis(&self, width: u32, height: u32) -> Result<[[f32; 4]; 4], RenderError> {
        let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cross = |a: [f32; 3], b: [f32; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let unit = |a: [f32; 3]| {
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            (n.is_finite() && n > 0.0).then(|| [a[0] / n, a[1] / n, a[2] / n])
        };
        let bad = || RenderError::Camera {
            eye: self.eye,
            target: self.target,
            fov_y_degrees: self.fov_y_degrees,
        };
        if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0)
            || self.eye.iter().chain(&self.target).any(|x| !x.is_finite())
        {
            return Err(bad());
        }
        let forward = unit(sub(self.target, self.eye)).ok_or_else(bad)?;
        let right = unit(cross(forward, [0.0, 1.0, 0.0])).ok_or_else(bad)?;
        let up = cross(right, forward);
        let half_h = (0.5 * self.fov_y_degrees.to_radians()).tan();
        let half_w = half_h * width as f32 / height as f32;
        let e = self.eye;
        Ok([
            [e[0], e[1], e[2], 0.0],
            [forward[0], forward[1], forward[2], 0.0],
            [right[0] * half_w, right[1] * half_w, right[2] * half_w, 0.0],
            [up[0] * half_h, up[1] * half_h, up[2] * half_h, 0.0],
        ])
    }
}

/// The unit vectors towards the target, right and up of a view along `-z`
/// tilted down by `slope` (rise over run).
fn view_axes(slope: f64) -> [[f64; 3]; 3] {
    let norm = (slope * slope + 1.0).sqrt();
    [
        [0.0, -slope / norm, -1.0 / norm],
        [1.0, 0.0, 0.0],
        [0.0, 1.0 / norm, -slope / norm],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The camera along `slope` that fits `points` (see [`Camera::fitting`]).
fn fit_along(points: &[[f64; 3]], slope: f64, aspect: f64) -> Camera {
    let [forward, right, up] = view_axes(slope);
    let first = points[0];
    let [lo, hi] = points.iter().fold([first, first], |[lo, hi], p| {
        [
            [0, 1, 2].map(|i| lo[i].min(p[i])),
            [0, 1, 2].map(|i| hi[i].max(p[i])),
        ]
    });
    let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
    let local: Vec<[f64; 3]> = points
        .iter()
        .map(|p| {
            let q = [0, 1, 2].map(|i| p[i] - centre[i]);
            [dot(q, right), dot(q, up), dot(q, forward)]
        })
        .collect();
    let extent = |k: usize| {
        local
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[a, b], p| {
                [a.min(p[k]), b.max(p[k])]
            })
    };
    let ([x0, x1], [y0, y1]) = (extent(0), extent(1));
    let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let fov: f64 = 40.0;
    let th = 0.95 * (0.5 * fov.to_radians()).tan();
    let tw = th * aspect;
    let size = (x1 - x0).max(y1 - y0).max(1e-6);
    // Every point in front of the eye, and inside the frame.
    let distance = local.iter().fold(0.0f64, |d, p| {
        d.max(1e-3 * size - p[2])
            .max((p[0] - xc).abs() / tw - p[2])
            .max((p[1] - yc).abs() / th - p[2])
    });
    let target = [0, 1, 2].map(|i| centre[i] + xc * right[i] + yc * up[i]);
    let eye = [0, 1, 2].map(|i| target[i] - distance * forward[i]);
    Camera {
        eye: eye.map(|x| x as f32),
        target: target.map(|x| x as f32),
        fov_y_degrees: fov as f32,
    }
}

/// The projected area of `triangles` under `camera`, over the picture's
/// (overlaps counted twice: an estimate of what the rays can hit).
fn coverage(camera: &Camera, triangles: &[[[f32; 3]; 3]], aspect: f64) -> f64 {
    let eye = camera.eye.map(f64::from);
    let to = [0, 1, 2].map(|i| f64::from(camera.target[i]) - eye[i]);
    let n = dot(to, to).sqrt();
    let forward = to.map(|x| x / n);
    let r = [-forward[2], 0.0, forward[0]];
    let rn = dot(r, r).sqrt();
    if !(n > 0.0 && rn > 0.0) {
        return 0.0;
    }
    let right = r.map(|x| x / rn);
    let up = [
        right[1] * forward[2] - right[2] * forward[1],
        right[2] * forward[0] - right[0] * forward[2],
        right[0] * forward[1] - right[1] * forward[0],
    ];
    let th = (0.5 * f64::from(camera.fov_y_degrees).to_radians()).tan();
    let tw = th * aspect;
    let project = |p: [f32; 3]| {
        let d = [0, 1, 2].map(|i| f64::from(p[i]) - eye[i]);
        let z = dot(d, forward).max(1e-9);
        [dot(d, right) / (z * tw), dot(d, up) / (z * th)]
    };
    let area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(project);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
        })
        .filter(|a| a.is_finite())
        .sum();
    area / 4.0
}
