//! The slow path of one sample: admitted under the input policy (a reading it holds or skips),
//! then taken as the first sample, one after a gap or a restart of the clock, or a step, with the
//! rest window's bias learnt and, when the window ends, the noise-scaled dead band and HDR bound.

use super::{Output, Pipeline};
use crate::input::{GapAction, NonFinite};
use crate::kernel::{Event, EventKind, Measured, Signal};
use crate::stage::Clock;
use crate::validate::usable_reading;

impl Pipeline {
    /// The interval and the reading to use for a sample under the input policy (the clock then
    /// moves to `t`), or `None` to skip the sample and leave everything as it was.
    pub(super) fn admit(
        &mut self,
        t: f64,
        rate: f64,
        temperature: Option<f64>,
    ) -> Option<(f64, f64, Option<f64>)> {
        // After a restart of the clock any time within range is taken, with no interval.
        let clock = if self.clock_restarted {
            Clock::default()
        } else {
            self.clock
        };
        let dt = clock.interval(t)?;
        let needs_temperature = self.config.correction.temperature.is_some();
        let reading =
            if usable_reading(rate, temperature) && (temperature.is_some() || !needs_temperature) {
                self.last_reading = Some((rate, temperature));
                (rate, temperature)
            } else {
                match (self.config.input.non_finite, self.last_reading) {
                    (NonFinite::Hold, Some(held)) => {
                        self.report.held = self.report.held.saturating_add(1);
                        held
                    }
                    _ => return None,
                }
            };
        self.clock.set(t);
        Some((dt, reading.0, reading.1))
    }

    /// The slow path for an admitted sample with interval `dt`: the first sample, a gap, the rest
    /// window and its end.
    pub(super) fn take(
        &mut self,
        first: bool,
        dt: f64,
        rate: f64,
        temperature: Option<f64>,
        speed: f64,
    ) -> Output {
        let t = self.clock.last().unwrap_or(f64::NAN);
        let policy = self.config.input;
        let kind = if first {
            EventKind::First
        } else if self.clock_restarted {
            // As after a gap, with no interval (`dt` is 0): a first sample for the stages the
            // policy keeps, and for the others a restart.
            self.clock_restarted = false;
            match policy.gap_action {
                GapAction::Reset => EventKind::AfterGap,
                GapAction::Bridge => EventKind::First,
            }
        } else if dt > policy.gap_limit {
            self.report.gap(dt);
            match policy.gap_action {
                GapAction::Reset => EventKind::AfterGap,
                GapAction::Bridge => EventKind::Step,
            }
        } else {
            EventKind::Step
        };
        if self.bias.learning() {
            self.bias.learn(self.config.correction.bias, t, dt, rate);
            self.engine.measured(&Measured {
                bias: Some(self.bias.value()),
                ..Measured::default()
            });
        }
        let measuring = self.bias.learning();
        if self.scaling_pending && !measuring {
            self.scale_to_rest();
        }
        let e = Event {
            dt,
            kind,
            measuring,
        };
        let x = Signal {
            speed,
            ..Signal::reading(rate, temperature.unwrap_or(f64::NAN))
        };
        Output::of(self.engine.event(e, x))
    }

    /// Sets the [`NoiseScaled`] dead band and HDR bound from the rest window that just ended.
    fn scale_to_rest(&mut self) {
        self.scaling_pending = false;
        let Some(rest) = self.bias.rest_statistics() else {
            return;
        };
        let scaled = self.config.noise_scaled;
        self.engine.measured(&Measured {
            bias: None,
            threshold: scaled.threshold_sigmas.map(|k| k * rest.noise),
            hdr_bound: scaled.hdr_bound_sigmas.map(|k| k * rest.bias_std_error),
            rest: Some(rest),
        });
    }
}
