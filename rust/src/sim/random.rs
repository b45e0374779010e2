//! The simulator's random numbers: xoshiro256++ seeded through SplitMix64 (both checked against
//! their reference outputs in the tests), and Gaussian deviates by the Box-Muller transform.

/// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit generator used to seed [`Xoshiro256PlusPlus`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The generator whose state starts at `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// xoshiro256++ (Blackman & Vigna 2019): fast, 256 bits of state, passes BigCrush.
///
/// Read back (`serde` feature), an all-zero state is refused: the generator would stay there and
/// give 0 for ever (a [`Sampler`](crate::sim::Sampler) that drops samples then never returned).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct Xoshiro256PlusPlus {
    s: [u64; 4],
}

impl Xoshiro256PlusPlus {
    /// The generator with the given raw state (which must not be all zero).
    pub fn from_state(s: [u64; 4]) -> Self {
        Xoshiro256PlusPlus { s }
    }

    /// Fails for the all-zero state, which the generator never leaves.
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self) -> Result<(), crate::Error> {
        if self.s == [0; 4] {
            return Err(crate::Error::InvalidParameter {
                name: "rng state",
                value: 0.0,
                valid: "not all zero (xoshiro256++ stays at zero): a state edited by hand or \
                        damaged; build the model again from its seed",
            });
        }
        Ok(())
    }

    /// Stream `stream` of `seed`: the state is four SplitMix64 outputs of a seed that mixes both,
    /// so different streams of one seed are unrelated (and never all zero).
    pub fn from_seed(seed: u64, stream: u64) -> Self {
        let mut mix = SplitMix64::new(seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03));
        // One extra round so that seeds differing in a few bits start far apart.
        let mut sm = SplitMix64::new(mix.next_u64());
        Xoshiro256PlusPlus {
            s: [sm.next_u64(), sm.next_u64(), sm.next_u64(), sm.next_u64()],
        }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let result = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// A uniform deviate in `[0, 1)` with 53 random bits.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Standard normal deviates by the Box-Muller transform; the second deviate of each pair is kept
/// for the next call.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Gaussian {
    rng: Xoshiro256PlusPlus,
    spare: Option<f64>,
}

impl Gaussian {
    /// Standard normal deviates from stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        Gaussian {
            rng: Xoshiro256PlusPlus::from_seed(seed, stream),
            spare: None,
        }
    }

    /// The next deviate (mean 0, variance 1).
    #[inline]
    pub fn sample(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // 1 - u lies in (0, 1], so the logarithm is finite.
        let radius = libm::sqrt(-2.0 * libm::log(1.0 - self.rng.uniform()));
        let angle = core::f64::consts::TAU * self.rng.uniform();
        self.spare = Some(radius * libm::sin(angle));
        radius * libm::cos(angle)
    }

    /// A uniform deviate in `[0, 1)` from the same stream.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        self.rng.uniform()
    }
}
