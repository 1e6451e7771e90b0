//! [`MicromapBuffers::check_for_khr_lossy`]: the rules of a Vulkan
//! `VK_KHR_opacity_micromap` build with
//! `VK_BUILD_ACCELERATION_STRUCTURE_MICROMAP_LOSSY_BIT_KHR`.

use super::{Api, BufferError, Format, IndexWidth, MicromapBuffers};

impl MicromapBuffers {
    /// Checks the buffers for a Vulkan KHR **lossy** build (bit 10,
    /// `VK_BUILD_ACCELERATION_STRUCTURE_MICROMAP_LOSSY_BIT_KHR`), beyond
    /// [`check_for`](Self::check_for)`(Api::VulkanKhr, width)`: every record
    /// (and so every usage entry) is 4-state
    /// (VUID-VkAccelerationStructureBuildGeometryInfoKHR-format-11712/11713),
    /// and every level is at most the device's
    /// `maxOpacityLossy4StateSubdivisionLevel`, passed as
    /// `max_lossy_level` (VUID-…-subdivisionLevel-11565/11567, which
    /// replace the 4-state limit in a lossy build). The first record that
    /// breaks a rule is the error.
    ///
    /// A lossy build may turn any state into an unknown one; the known
    /// states written here stay conservative either way.
    ///
    /// ```
    /// use micromap_index::micromap::{BufferError, Format, IndexWidth, Micromap, MicromapBuffers, State, TriangleOpacity};
    /// use micromap_index::Level;
    /// let four = Micromap::from_states(Level::new(3).unwrap(), Format::FourState, State::ALL.into_iter().cycle().take(64)).unwrap();
    /// let buffers = MicromapBuffers::build([TriangleOpacity::Micromap(&four)], Default::default()).unwrap();
    /// assert_eq!(buffers.check_for_khr_lossy(IndexWidth::U16, 3), Ok(()));
    /// assert!(matches!(buffers.check_for_khr_lossy(IndexWidth::U16, 2), Err(BufferError::LevelNotAllowed { level: 3, max: 2, .. })));
    /// let two = Micromap::from_states(Level::new(1).unwrap(), Format::TwoState, [State::Opaque, State::Transparent, State::Opaque, State::Opaque]).unwrap();
    /// let buffers = MicromapBuffers::build([TriangleOpacity::Micromap(&two)], Default::default()).unwrap();
    /// assert_eq!(buffers.check_for_khr_lossy(IndexWidth::U16, 12), Err(BufferError::FormatNotAllowed { record: 0, format: 1 }));
    /// ```
    pub fn check_for_khr_lossy(
        &self,
        width: IndexWidth,
        max_lossy_level: u32,
    ) -> Result<(), BufferError> {
        self.check_for(Api::VulkanKhr, width)?;
        for (record, r) in self.records().iter().enumerate() {
            if r.format != Format::FourState.raw() {
                return Err(BufferError::FormatNotAllowed {
                    record,
                    format: r.format,
                });
            }
            if u32::from(r.subdivision_level) > max_lossy_level {
                return Err(BufferError::LevelNotAllowed {
                    level: u32::from(r.subdivision_level),
                    max: max_lossy_level,
                    api: Api::VulkanKhr,
                });
            }
        }
        Ok(())
    }
}
