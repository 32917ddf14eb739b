//! Enums whose values have one spelling: the name on the command line, in reports, in JSON and
//! in the viewer's title is written once, in the enum's definition.

/// Defines a fieldless enum whose variants each have one name, with `ALL`, `name()`,
/// `clap::ValueEnum` (so the command line parses it) and `serde::Serialize` (as the name).
/// The variant marked `#[default]` is the default.
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $text:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        $vis enum $name {
            $( $(#[$vmeta])* $variant ),+
        }

        impl $name {
            /// Every value, in definition order.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];

            /// Its one spelling.
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }
        }

        impl clap::ValueEnum for $name {
            fn value_variants<'a>() -> &'a [Self] {
                Self::ALL
            }

            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                Some(clap::builder::PossibleValue::new(self.name()))
            }
        }

        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.serialize_str(self.name())
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

pub(crate) use named_enum;

#[cfg(test)]
mod tests {
    super::named_enum! {
        /// A test enum.
        enum Colour {
            #[default]
            Red = "red",
            Dark = "dark-blue",
        }
    }

    #[test]
    fn one_spelling_everywhere() {
        use clap::ValueEnum;
        assert_eq!(Colour::default(), Colour::Red);
        assert_eq!(Colour::Dark.name(), "dark-blue");
        assert_eq!(Colour::from_str("dark-blue", false), Ok(Colour::Dark));
        assert_eq!(serde_json::to_string(&Colour::Dark).ok().as_deref(), Some("\"dark-blue\""));
        assert_eq!(Colour::ALL, &[Colour::Red, Colour::Dark]);
    }
}
