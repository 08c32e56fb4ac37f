//! What the grammar targets (`pbrt_grammar`, `scene_grammar`) share.

/// An enumeration of fixed words (names, kinds, parameter names) that
/// `arbitrary` picks from, each with its text.
macro_rules! words {
    ($name:ident { $($variant:ident = $text:literal),* $(,)? }) => {
        #[derive(Arbitrary, Debug, Clone, Copy)]
        enum $name { $($variant),* }
        impl $name {
            fn text(self) -> &'static str {
                match self { $($name::$variant => $text),* }
            }
        }
    };
}
