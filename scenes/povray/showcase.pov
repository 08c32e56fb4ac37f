// POV-Ray 3.7 translation of scenes/showcase.toml (lucent's classic Whitted
// showcase), object for object, for the speed comparison of issue 11
// (scripts/povray-compare.sh, docs/performance.md).
//
// Render (as the comparison does):
//   povray +Iscenes/povray/showcase.pov +W800 +H600 +A0.0 +AM1 +R3 +WT2 -D \
//          File_Gamma=sRGB +Oshowcase-povray.png
//
// How lucent's model maps onto POV-Ray's (see docs/scene-format.md §10 and
// crates/lucent/src/integrator/whitted.rs):
//
// * Coordinates. lucent is right-handed, y up; POV-Ray is left-handed. All
//   coordinates, rotations and scales are written with the same numbers
//   (POV's `rotate z*A` turns x towards y, like lucent's rotate_z = A, and
//   applies transforms in the order written, like lucent). Only the camera
//   differs: lucent's image right is u = w × up, which is -x when looking
//   along +z, so the camera's `right` vector is negated. Without that the
//   POV image would be mirrored left to right.
// * Camera. lucent's `fov` is the HORIZONTAL field of view (tan(fov/2) spans
//   half the image width, pixels square), which is what POV's `angle` is, so
//   angle = fov = 55 at any aspect ratio.
// * Shading. lucent computes, per light that is above the surface and not
//   shadowed, (kd·C/π + ks·max(0, r·wo)^exponent) · E · (n·wi), plus
//   ka·C·A ambient (ka = kd) and kr times the mirror ray. So:
//     ambient  = kd, with global ambient_light = [ambient] colour·intensity
//               (0.08): POV multiplies the two and the pigment, no shadows;
//     diffuse  = kd/π (POV's diffuse term has no 1/π), brilliance 1;
//     phong    = ks·cosI, phong_size = exponent: POV's phong highlight is
//               phong·(r·wo)^size·E with NO n·wi factor, lucent's has one.
//               cosI is n·wi at the peak of the key light's highlight
//               (computed for this scene: mirror ball 0.91, green 0.92,
//               gold sphere 0.90, violet triangle 0.95); the second light's
//               highlights come out ~10-15% brighter in POV-Ray than in
//               lucent;
//     reflection = kr (white, added on top, not tinted; no fresnel, no
//               metallic, no conserve_energy).
//   Phong and mirror highlights in lucent are white, as in POV without
//   `metallic`.
// * Lights. lucent's point lights with the default falloff = "none" deliver
//   colour·intensity at any distance: POV light_source with colour
//   colour·intensity and no fade_distance/fade_power (no attenuation).
// * Depth. lucent's max_depth = 5 follows at most 5 mirror bounces and
//   shades the deepest surface without its mirror term (6 surfaces shaded on
//   a path). POV's max_trace_level counts the camera ray as level 1 and a
//   ray past the limit returns black, so max_trace_level = 6 is the same
//   (checked with two facing half-mirrors). adc_bailout 0: lucent stops on
//   depth only, never on a small path weight (POV's default 1/255 would cut
//   the gold's 0.3^5 paths).
// * Checker. lucent's plane checker uses u = x, v = -z (normal +y) and
//   colours the even colour where floor(u/1.5)+floor(v/1.5) is even; POV's
//   checker uses floor(x)+floor(y)+floor(z) (y = 0 on the floor). floor(-t)
//   = -floor(t)-1, so the parities are swapped: color 1 is lucent's `odd`.
// * Background: plain background colour (lucent's rays that leave see it,
//   camera and mirror rays alike).
// * Colours are linear (assumed_gamma 1.0). lucent's tone_map = "classic"
//   divides a pixel by its largest channel if that exceeds 1 and then
//   sRGB-encodes; POV clips each channel at 1 and encodes with File_Gamma
//   (pass File_Gamma=sRGB). They differ only in over-exposed highlights.
// * Anti-aliasing: lucent 9 spp on a jittered 3×3 grid per pixel with a box
//   filter; POV +A0.0 +AM1 +R3 (threshold 0: every pixel that differs from a
//   neighbour is supersampled with a jittered 3×3 grid).

#version 3.7;

global_settings {
  assumed_gamma 1.0
  max_trace_level 6
  adc_bailout 0
  ambient_light rgb 0.08
}

background { rgb <0.05, 0.07, 0.12> }

camera {
  perspective
  location <0, 3.2, -11>
  sky y
  up y
  right -x*image_width/image_height
  angle 55
  look_at <0, 1.1, 0>
}

#declare Pi = 3.14159265358979;

light_source { <-6, 9, -7> rgb <1, 0.95, 0.9>*1.4 }
light_source { <7, 6, -3> rgb <0.6, 0.7, 1.0>*0.6 }

// Materials: [materials.*] of showcase.toml.
#declare T_Floor = texture {
  pigment { checker rgb <0.15, 0.15, 0.18>, rgb <0.85, 0.85, 0.8> scale 1.5 }
  finish { ambient 0.9 diffuse 0.9/Pi phong 0 specular 0 reflection 0 }
}
#declare T_Red = texture {
  pigment { rgb <0.9, 0.15, 0.1> }
  finish { ambient 0.9 diffuse 0.9/Pi phong 0 specular 0 reflection 0 }
}
#declare T_Mirror = texture {
  pigment { rgb <0.9, 0.9, 0.95> }
  finish { ambient 0.1 diffuse 0.1/Pi phong 0.8*0.91 phong_size 200 specular 0 reflection 0.85 }
}
#declare T_Green = texture {
  pigment { rgb <0.2, 0.8, 0.3> }
  finish { ambient 0.7 diffuse 0.7/Pi phong 0.6*0.92 phong_size 40 specular 0 reflection 0.15 }
}
#declare T_Gold = texture {
  pigment { rgb <1.0, 0.75, 0.25> }
  finish { ambient 0.6 diffuse 0.6/Pi phong 0.9*0.90 phong_size 80 specular 0 reflection 0.3 }
}
#declare T_Blue = texture {
  pigment { rgb <0.2, 0.35, 0.95> }
  finish { ambient 0.9 diffuse 0.9/Pi phong 0 specular 0 reflection 0 }
}
#declare T_Violet = texture {
  pigment { rgb <0.75, 0.35, 0.9> }
  finish { ambient 0.8 diffuse 0.8/Pi phong 0.4*0.95 phong_size 20 specular 0 reflection 0 }
}

// floor
plane { y, 0 texture { T_Floor } }
// mirror ball
sphere { <0, 1.5, 1.5>, 1.5 texture { T_Mirror } }
// red matte
sphere { <-3.2, 1, -0.5>, 1 texture { T_Red } }
// green phong
sphere { <3.0, 0.9, -0.8>, 0.9 texture { T_Green } }
// small gold
sphere { <1.3, 0.45, -2.6>, 0.45 texture { T_Gold } }
// ellipsoid: the unit sphere scaled, turned about z, moved (lucent's order)
sphere {
  <0, 0, 0>, 1
  texture { T_Blue }
  scale <0.6, 1.3, 0.6>
  rotate z*-25
  translate <-1.6, 1.25, 3.2>
}
// smooth: per-vertex normals
smooth_triangle {
  <2.2, 0.01, 2.0>, <-0.7, 0.3, -0.65>,
  <5.2, 0.01, 3.5>, <0.7, 0.3, -0.65>,
  <3.6, 3.0, 3.0>, <0, 0.9, -0.45>
  texture { T_Violet }
}
// flat: standing on the floor
triangle {
  <-5.6, 0.01, 1.5>, <-3.4, 0.01, 3.5>, <-4.6, 2.6, 2.5>
  texture { T_Gold }
}
