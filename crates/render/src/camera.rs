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
