//! What a render is asked for beyond the scene and the technique: the light samples of the
//! sampled techniques.

use penumbra_geom::Technique;
use penumbra_volumes::SamplePattern;

use crate::error::RenderError;

/// The most light samples per pixel (256 x 256): beyond, a 320 x 240 reference would take hours
/// and the sampling error is far below `f32`'s resolution of V anyway.
pub const MAX_SAMPLES: usize = 65536;

/// How the sampled techniques (`reference`, `depth-complexity`) sample the light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Light samples per pixel, a perfect square (64, 256, 1024, ...).
    pub samples: usize,
    /// `depth-complexity`: the reference's jittered points instead of its own multi-jittered
    /// ones, so that the two images agree pixel for pixel.
    pub jitter: bool,
}

impl Default for RenderOptions {
    /// 256 samples, not jittered.
    fn default() -> Self {
        RenderOptions {
            samples: 256,
            jitter: false,
        }
    }
}

impl RenderOptions {
    /// The sample pattern, or an error for a sample count that is not a positive square up to
    /// [`MAX_SAMPLES`].
    ///
    /// ```
    /// use penumbra::RenderOptions;
    ///
    /// let p = RenderOptions { samples: 1024, jitter: true }.pattern().unwrap();
    /// assert_eq!((p.per_axis, p.jitter), (32, true));
    /// assert!(RenderOptions { samples: 1000, jitter: false }.pattern().is_err());
    /// assert!(RenderOptions { samples: 65536 * 4, jitter: false }.pattern().is_err());
    /// ```
    pub fn pattern(&self) -> Result<SamplePattern, RenderError> {
        let n = (self.samples as f64).sqrt().round() as usize;
        if self.samples == 0 || n * n != self.samples || self.samples > MAX_SAMPLES {
            return Err(RenderError::BadSamples {
                samples: self.samples,
            });
        }
        Ok(SamplePattern {
            per_axis: n,
            jitter: self.jitter,
        })
    }

    /// The sample pattern `technique` renders with: [`RenderOptions::pattern`], and an error
    /// for jitter asked of a technique that takes no light samples. Every render checks its
    /// options with it; a program may call it first to refuse bad options before any work.
    ///
    /// ```
    /// use penumbra::{RenderError, RenderOptions, Technique};
    ///
    /// let jittered = RenderOptions { samples: 64, jitter: true };
    /// assert!(jittered.pattern_for(Technique::DepthComplexity).is_ok());
    /// assert!(matches!(
    ///     jittered.pattern_for(Technique::Wedges),
    ///     Err(RenderError::NoSamples { technique: Technique::Wedges })
    /// ));
    /// ```
    pub fn pattern_for(&self, technique: Technique) -> Result<SamplePattern, RenderError> {
        let pattern = self.pattern()?;
        if self.jitter && !technique.takes_samples() {
            return Err(RenderError::NoSamples { technique });
        }
        Ok(pattern)
    }
}
