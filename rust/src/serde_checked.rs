//! Serde for a state that must be checked when it is read back: a [`Pipeline`], [`Fusion`],
//! [`FusedPipeline`], [`Correction`], [`Downsample`], stand-alone [`Streaming`] stage,
//! [`GyroModel`] or random generator edited by hand, damaged, or saved by another version ran with
//! values its `new` refuses (a negative low-pass `tau` in the stored stages gave NaN headings,
//! a negative gate rejected every fix) or with stages other than its configuration says.
//!
//! The type derives its serde code as inherent functions (`#[serde(remote = "Self")]`), and
//! [`checked_serde!`] implements the traits on them: serialising as derived, deserialising as
//! derived and then checked, the check's error (the core's, in its words) the deserialiser's.

use crate::kernel::Validated;
use crate::sim::Xoshiro256PlusPlus;
use crate::{Correction, Downsample, Error, FusedPipeline, Fusion, GyroModel, Pipeline, Streaming};

/// Implements `Serialize` and `Deserialize` for `$ty` (generic over `[$g]`, if given) from its
/// `remote = "Self"` derive, the deserialised value checked by `$check: fn(&$ty) -> Result<(),
/// Error>`, or made whole by `$restore: fn($ty) -> Result<$ty, Error>` (`$ty => $restore`).
macro_rules! checked_serde {
    ([$($g:tt)*] $ty:ty => $restore:expr) => {
        impl<$($g)*> serde::Serialize for $ty {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                // the derived (inherent) function, not this trait's
                <$ty>::serialize(self, serializer)
            }
        }

        impl<'de, $($g)*> serde::Deserialize<'de> for $ty {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                let value = <$ty>::deserialize(deserializer)?;
                let restore: fn($ty) -> Result<$ty, Error> = $restore;
                restore(value).map_err(<D::Error as serde::de::Error>::custom)
            }
        }
    };
    ([$($g:tt)*] $ty:ty, $check:expr) => {
        checked_serde!([$($g)*] $ty => |value| {
            let check: fn(&$ty) -> Result<(), Error> = $check;
            check(&value).map(|()| value)
        });
    };
    ($ty:ty => $restore:expr) => {
        checked_serde!([] $ty => $restore);
    };
    ($ty:ty, $check:expr) => {
        checked_serde!([] $ty, $check);
    };
}

checked_serde!(Pipeline, Pipeline::check_restored);
checked_serde!(Fusion, Fusion::check_restored);
checked_serde!(FusedPipeline, FusedPipeline::check_restored);
checked_serde!(Correction, Correction::check_restored);
checked_serde!(Downsample, Downsample::check_restored);
checked_serde!([K: Validated] Streaming<K>, Streaming::check_restored);
checked_serde!(GyroModel => GyroModel::restored);
checked_serde!(Xoshiro256PlusPlus, Xoshiro256PlusPlus::check);
