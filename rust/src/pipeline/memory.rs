//! How the pipeline drives its stages with memory (low-pass, HDR, de-lag) and the integrator:
//! one generic loop for every combination of enabled stages, and primed copies of the stages for
//! the loop over a block's settled samples.

use core::marker::PhantomData;

use crate::hdr::{Hdr, HdrState, PrimedHdr};
use crate::integrate::{Integrator, PrimedIntegrator};
use crate::lowpass::{DeLag, LowPass, PrimedDeLag, PrimedLowPass};

/// One sample through a stage with memory (low-pass, HDR, de-lag) or the integrator, as the
/// pipeline drives it.
///
/// Implemented for each such stage, for its primed form (see [`Memory::primed`]), for `Option`
/// of them and for [`Off`], so that one generic loop serves every combination of enabled stages:
/// with all of them on (the HDR presets) or all off (the others) the loop is compiled for the
/// concrete stages and has no per-sample check of which are enabled.
pub(super) trait Feed {
    /// Feeds one sample with interval `dt`; the value the pipeline uses (see each impl).
    fn feed(&mut self, dt: f64, rate: f64) -> f64;
}

/// A stage the configuration may leave out.
pub(super) trait Optional: Feed {
    /// What [`Feed::feed`] gives while the stage is off.
    fn off(rate: f64) -> f64;
}

/// A stage with memory as the pipeline keeps it.
pub(super) trait Memory: Optional {
    /// Forgets the recent signal (after a gap, with [`crate::input::GapAction::Reset`]).
    fn restart(&mut self);
    /// Bounds the correction to what the rest window allows (see [`super::NoiseScaled`]); only HDR
    /// makes one.
    fn bound(&mut self, _bound: f64) {}
    /// The stage for the block loop's settled samples (see `Chain::primed_span`): a copy of
    /// its state without the first-sample case, which may borrow what does not change.
    type Primed<'a>: Optional
    where
        Self: 'a;
    /// What of a primed stage changes.
    type State;
    /// The primed stage, or `None` before its first sample.
    fn primed(&self) -> Option<Self::Primed<'_>>;
    /// What `primed` has changed, for [`Memory::set_state`].
    fn state<'a>(primed: Self::Primed<'a>) -> Self::State
    where
        Self: 'a;
    /// Takes over the `state` of a primed copy of the stage.
    fn set_state(&mut self, state: Self::State);
}

/// Implements [`Feed`] for stages by their own method of that signature.
macro_rules! feed_by {
    ($method:ident: $($ty:ty),+) => {
        $(
            impl Feed for $ty {
                #[inline(always)]
                fn feed(&mut self, dt: f64, rate: f64) -> f64 {
                    self.$method(dt, rate)
                }
            }
        )+
    };
}
// The filters pass the rate on, HDR gives the `I` to add, the integrator the heading.
feed_by!(step: LowPass, PrimedLowPass, DeLag, PrimedDeLag, Integrator);
feed_by!(observe: Hdr, PrimedHdr<'_>);

impl<const TRAPEZOID: bool> Feed for PrimedIntegrator<TRAPEZOID> {
    #[inline(always)]
    fn feed(&mut self, dt: f64, rate: f64) -> f64 {
        self.step(dt, rate)
    }
}

/// Implements [`Optional`] for stages that give `$off` (of `$rate`) while off.
macro_rules! off_gives {
    (|$rate:ident| $off:expr; $($ty:ty),+) => {
        $(
            impl Optional for $ty {
                #[inline(always)]
                fn off($rate: f64) -> f64 {
                    $off
                }
            }
        )+
    };
}
// A filter that is off passes the rate unchanged; HDR off adds nothing.
off_gives!(|rate| rate; LowPass, PrimedLowPass, DeLag, PrimedDeLag);
off_gives!(|_rate| 0.0; Hdr, PrimedHdr<'_>);

/// Implements [`Memory`] for a filter of the rate whose primed form is all its changing state.
macro_rules! rate_filter_memory {
    ($ty:ty, $primed:ty) => {
        impl Memory for $ty {
            #[inline(always)]
            fn restart(&mut self) {
                crate::stage::Stage::reset(self);
            }
            type Primed<'a> = $primed;
            type State = $primed;
            #[inline(always)]
            fn primed(&self) -> Option<$primed> {
                <$ty>::primed(self)
            }
            #[inline(always)]
            fn state<'a>(primed: $primed) -> $primed
            where
                Self: 'a,
            {
                primed
            }
            #[inline(always)]
            fn set_state(&mut self, state: $primed) {
                self.set_primed(state);
            }
        }
    };
}
rate_filter_memory!(LowPass, PrimedLowPass);
rate_filter_memory!(DeLag, PrimedDeLag);

/// HDR's bound survives a restart.
impl Memory for Hdr {
    #[inline(always)]
    fn restart(&mut self) {
        Hdr::restart(self);
    }
    fn bound(&mut self, bound: f64) {
        self.bound_correction(bound);
    }
    type Primed<'a> = PrimedHdr<'a>;
    type State = HdrState;
    #[inline(always)]
    fn primed(&self) -> Option<PrimedHdr<'_>> {
        Some(Hdr::primed(self))
    }
    #[inline(always)]
    fn state<'a>(primed: PrimedHdr<'a>) -> HdrState
    where
        Self: 'a,
    {
        primed.into_state()
    }
    #[inline(always)]
    fn set_state(&mut self, state: HdrState) {
        Hdr::set_state(self, state);
    }
}

impl<F: Optional> Feed for Option<F> {
    #[inline(always)]
    fn feed(&mut self, dt: f64, rate: f64) -> f64 {
        match self {
            Some(f) => f.feed(dt, rate),
            None => F::off(rate),
        }
    }
}

impl<F: Optional> Optional for Option<F> {
    #[inline(always)]
    fn off(rate: f64) -> f64 {
        F::off(rate)
    }
}

/// A stage that is off is primed (it has no first sample to wait for).
impl<M: Memory> Memory for Option<M> {
    #[inline(always)]
    fn restart(&mut self) {
        if let Some(m) = self {
            m.restart();
        }
    }
    fn bound(&mut self, bound: f64) {
        if let Some(m) = self {
            m.bound(bound);
        }
    }
    type Primed<'a>
        = Option<M::Primed<'a>>
    where
        M: 'a;
    type State = Option<M::State>;
    #[inline(always)]
    fn primed(&self) -> Option<Self::Primed<'_>> {
        match self {
            Some(m) => m.primed().map(Some),
            None => Some(None),
        }
    }
    #[inline(always)]
    fn state<'a>(primed: Self::Primed<'a>) -> Self::State
    where
        Self: 'a,
    {
        primed.map(M::state)
    }
    #[inline(always)]
    fn set_state(&mut self, state: Self::State) {
        if let (Some(m), Some(s)) = (self, state) {
            m.set_state(s);
        }
    }
}

/// A stage known to be off: an `Option` that is always `None`, so that a loop compiled for it
/// has no per-sample check (the presets without HDR have every stage with memory off).
pub(super) struct Off<M>(PhantomData<M>);

impl<M> Off<M> {
    pub(super) const OFF: Self = Off(PhantomData);
}

impl<M: Optional> Feed for Off<M> {
    #[inline(always)]
    fn feed(&mut self, _dt: f64, rate: f64) -> f64 {
        M::off(rate)
    }
}

impl<M: Optional> Optional for Off<M> {
    #[inline(always)]
    fn off(rate: f64) -> f64 {
        M::off(rate)
    }
}

impl<M: Optional> Memory for Off<M> {
    #[inline(always)]
    fn restart(&mut self) {}
    type Primed<'a>
        = Off<M>
    where
        M: 'a;
    type State = ();
    #[inline(always)]
    fn primed(&self) -> Option<Off<M>> {
        Some(Off::OFF)
    }
    #[inline(always)]
    fn state<'a>(_primed: Off<M>)
    where
        Self: 'a,
    {
    }
    #[inline(always)]
    fn set_state(&mut self, _state: ()) {}
}

/// The stages with memory are borrowed for a block or a sample.
impl<F: Feed> Feed for &mut F {
    #[inline(always)]
    fn feed(&mut self, dt: f64, rate: f64) -> f64 {
        (**self).feed(dt, rate)
    }
}

impl<F: Optional> Optional for &mut F {
    #[inline(always)]
    fn off(rate: f64) -> f64 {
        F::off(rate)
    }
}

impl<M: Memory> Memory for &mut M {
    #[inline(always)]
    fn restart(&mut self) {
        (**self).restart();
    }
    fn bound(&mut self, bound: f64) {
        (**self).bound(bound);
    }
    type Primed<'a>
        = M::Primed<'a>
    where
        Self: 'a;
    type State = M::State;
    #[inline(always)]
    fn primed(&self) -> Option<Self::Primed<'_>> {
        (**self).primed()
    }
    #[inline(always)]
    fn state<'a>(primed: Self::Primed<'a>) -> Self::State
    where
        Self: 'a,
    {
        M::state(primed)
    }
    #[inline(always)]
    fn set_state(&mut self, state: Self::State) {
        (**self).set_state(state);
    }
}
