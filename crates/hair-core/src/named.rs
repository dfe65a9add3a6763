//! Fixed-choice options with their names written once: [`named_enum!`](crate::named_enum)
//! declares an enum of unit variants, each with its name, and gives it `ALL`, `NAMES`, `name()`,
//! `Display`, `FromStr` (an [`UnknownName`] error listing the names) and serde's `Serialize` and
//! `Deserialize` as those names. Scene files, checkpoints, reports and the command line
//! (through [`Named`]) all read and write the same names.
//!
//! ```
//! hair_core::named_enum! {
//!     /// A fruit.
//!     #[derive(Debug, Clone, Copy, PartialEq, Eq)]
//!     pub enum Fruit {
//!         /// Red or green.
//!         Apple = "apple",
//!         /// Yellow.
//!         Banana = "banana",
//!     }
//! }
//! assert_eq!(Fruit::NAMES, ["apple", "banana"]);
//! assert_eq!("banana".parse::<Fruit>().unwrap(), Fruit::Banana);
//! let error = "cherry".parse::<Fruit>().unwrap_err();
//! assert_eq!(error.to_string(), "\"cherry\": expected one of apple, banana");
//! ```

use std::fmt;

/// A name that is none of an option's ([`Named`]'s `FromStr`): the name given and the allowed
/// ones.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownName {
    /// The name given.
    pub name: String,
    /// The allowed names.
    pub allowed: &'static [&'static str],
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?}: expected one of {}",
            self.name,
            self.allowed.join(", ")
        )
    }
}

impl std::error::Error for UnknownName {}

/// A fixed-choice option declared with [`named_enum!`](crate::named_enum): every value and its
/// name, for code generic over options (the command line's value parsers).
pub trait Named: Copy + Send + Sync + 'static {
    /// Every value, in declaration order.
    fn all() -> &'static [Self];
    /// Every value's name, in declaration order.
    fn names() -> &'static [&'static str];
    /// This value's name.
    fn name(self) -> &'static str;
    /// The value called `name`, or an [`UnknownName`] error listing the names.
    fn from_name(name: &str) -> Result<Self, UnknownName> {
        Self::all()
            .iter()
            .copied()
            .find(|value| value.name() == name)
            .ok_or_else(|| UnknownName {
                name: name.to_owned(),
                allowed: Self::names(),
            })
    }
}

/// Declares an enum of unit variants with one name each (`Variant = "name"`), and implements
/// for it: `ALL` and `NAMES` (declaration order), `name()`, [`Named`], `Display` (the name),
/// `FromStr` (an [`UnknownName`] error listing the names), and serde's `Serialize` and
/// `Deserialize` as the name. Attributes and doc comments pass through, `#[default]` included.
#[macro_export]
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $enum:ident {
            $( $(#[$variant_meta:meta])* $variant:ident = $name:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis enum $enum {
            $( $(#[$variant_meta])* $variant ),+
        }

        impl $enum {
            /// Every value, in declaration order.
            pub const ALL: [$enum; [$($name),+].len()] = [$($enum::$variant),+];
            /// Every value's name (scene files, the command line, reports), in declaration order.
            pub const NAMES: [&'static str; [$($name),+].len()] = [$($name),+];

            /// The value's name in scene files, on the command line and in reports.
            pub const fn name(self) -> &'static str {
                match self {
                    $($enum::$variant => $name),+
                }
            }
        }

        impl $crate::named::Named for $enum {
            fn all() -> &'static [Self] {
                &Self::ALL
            }
            fn names() -> &'static [&'static str] {
                &Self::NAMES
            }
            fn name(self) -> &'static str {
                $enum::name(self)
            }
        }

        impl ::std::fmt::Display for $enum {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl ::std::str::FromStr for $enum {
            type Err = $crate::named::UnknownName;
            fn from_str(text: &str) -> ::std::result::Result<Self, Self::Err> {
                <$enum as $crate::named::Named>::from_name(text)
            }
        }

        impl $crate::named::serde::Serialize for $enum {
            fn serialize<S: $crate::named::serde::Serializer>(
                &self,
                serializer: S,
            ) -> ::std::result::Result<S::Ok, S::Error> {
                serializer.serialize_str(self.name())
            }
        }

        impl<'de> $crate::named::serde::Deserialize<'de> for $enum {
            fn deserialize<D: $crate::named::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<Self, D::Error> {
                deserializer.deserialize_str($crate::named::NameVisitor::<$enum>::new())
            }
        }
    };
}

#[doc(hidden)]
pub use serde;

/// serde's visitor of a [`Named`] option: a string that is one of its names.
#[doc(hidden)]
pub struct NameVisitor<T>(std::marker::PhantomData<T>);

impl<T> NameVisitor<T> {
    /// A visitor of `T`'s names.
    pub fn new() -> Self {
        NameVisitor(std::marker::PhantomData)
    }
}

impl<T> Default for NameVisitor<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Named> serde::de::Visitor<'_> for NameVisitor<T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "one of {}", T::names().join(", "))
    }

    fn visit_str<E: serde::de::Error>(self, text: &str) -> Result<T, E> {
        T::from_name(text).map_err(E::custom)
    }
}

#[cfg(test)]
mod tests {
    crate::named_enum! {
        /// A test option.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
        enum Weather {
            /// The default.
            #[default]
            Calm = "calm",
            Windy = "windy",
            BlowingAGale = "blowing-a-gale",
        }
    }

    #[test]
    fn names_round_trip_through_text_and_serde() {
        assert_eq!(Weather::default(), Weather::Calm);
        for weather in Weather::ALL {
            assert_eq!(weather.name().parse::<Weather>().unwrap(), weather);
            let json = serde_json::to_string(&weather).unwrap();
            assert_eq!(json, format!("\"{}\"", weather.name()));
            assert_eq!(serde_json::from_str::<Weather>(&json).unwrap(), weather);
            assert_eq!(weather.to_string(), weather.name());
        }
        assert_eq!(Weather::NAMES, ["calm", "windy", "blowing-a-gale"]);
    }

    #[test]
    fn an_unknown_name_lists_the_allowed_ones() {
        let expected = "\"foggy\": expected one of calm, windy, blowing-a-gale";
        assert_eq!(
            "foggy".parse::<Weather>().unwrap_err().to_string(),
            expected
        );
        let error = serde_json::from_str::<Weather>("\"foggy\"").unwrap_err();
        assert!(error.to_string().starts_with(expected), "{error}");
        // Not a string at all: serde's message says what was expected.
        let error = serde_json::from_str::<Weather>("3").unwrap_err();
        assert!(error.to_string().contains("one of calm"), "{error}");
    }
}
