//! [`wgsl_struct!`](crate::wgsl_struct): a struct the CPU writes and a shader reads, declared
//! once. From one list of fields it declares the `#[repr(C)]` Rust struct and, as the associated
//! constant `WGSL`, the WGSL declaration of the same struct (the fields in the same order, each
//! with its WGSL type and its doc comment), which the renderer composes into the shaders that
//! import it; `FIELDS` gives each field's byte offset in the Rust struct, against which a test
//! checks the offsets WGSL gives the declaration. Text only: this crate knows no GPU.

/// Declares a `#[repr(C)]` struct shared with WGSL, and its WGSL declaration.
///
/// Each field is written `name: RustType as "wgsl_type"`, with doc comments only; the struct
/// may take other attributes (derives). `struct Rust as Wgsl` names the WGSL struct otherwise
/// than the Rust one. The struct gets two associated constants: `WGSL`, the declaration
/// (`struct Wgsl { … }`), and `FIELDS`, each field's name and byte offset.
///
/// ```
/// grove_systems::wgsl_struct! {
///     /// A point and its weight.
///     #[derive(Clone, Copy)]
///     pub struct Weighted as WeightedPoint {
///         /// Where it is.
///         pub at: [f32; 3] as "vec3<f32>",
///         /// How much it counts.
///         pub weight: f32 as "f32",
///     }
/// }
/// assert_eq!(Weighted::WGSL, "struct WeightedPoint {\n    // Where it is.\n    at: vec3<f32>,\n    // How much it counts.\n    weight: f32,\n}\n");
/// assert_eq!(Weighted::FIELDS, [("at", 0), ("weight", 12)]);
/// ```
#[macro_export]
macro_rules! wgsl_struct {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident as $wgsl_name:ident {
            $( $(#[doc = $doc:literal])* $fvis:vis $field:ident : $rty:ty as $wgsl:literal ),* $(,)?
        }
    ) => {
        #[repr(C)]
        $(#[$meta])*
        $vis struct $name {
            $( $(#[doc = $doc])* $fvis $field: $rty, )*
        }

        impl $name {
            /// The WGSL declaration of this struct: its fields in order, with their WGSL types and
            /// doc comments (`wgsl_struct!`).
            pub const WGSL: &'static str =
                concat!("struct ", stringify!($wgsl_name), " {\n", $( $("    //", $doc, "\n",)* "    ", stringify!($field), ": ", $wgsl, ",\n", )* "}\n");
            /// Each field's name and byte offset in this struct, in order (`wgsl_struct!`).
            pub const FIELDS: &'static [(&'static str, usize)] = &[$( (stringify!($field), ::core::mem::offset_of!($name, $field)), )*];
        }
    };
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $( $body:tt )*
        }
    ) => {
        $crate::wgsl_struct! {
            $(#[$meta])*
            $vis struct $name as $name {
                $( $body )*
            }
        }
    };
}
