//! Participating media against closed forms: Beer–Lambert transmittance,
//! a furnace of a medium that only scatters, and single scattering in a
//! slab; and how pbrt-v4's `MakeNamedMedium`/`MediumInterface` place media
//! (the camera's medium, boundaries without a surface, media on both
//! sides of a glass).

use lucent::color::Color;
use lucent::loader::pbrt::{import_pbrt, ImportOptions};
use lucent::loader::LoadedScene;
use lucent::render::{render, RenderOptions};
use std::f32::consts::PI;

fn import(text: &str) -> Result<LoadedScene, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    import_pbrt(&path, &ImportOptions::default()).map_err(|e| e.to_string())
}

/// The mean colour of an imported scene's image at its own settings.
fn mean(text: &str) -> Color {
    let s = import(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let film = render(&s.scene, &s.settings, RenderOptions::default()).unwrap().film;
    film.pixels().iter().copied().sum::<Color>() / film.pixels().len() as f32
}

/// A camera at the centre of a sphere of radius 2 filled with `medium`
/// (its boundary an `interface`), under a white environment.
fn inside_sphere(medium: &str, spp: u32) -> String {
    format!(
        "MediumInterface \"m\" \"m\"\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\
         Sampler \"independent\" \"integer pixelsamples\" {spp}\nIntegrator \"volpath\" \"integer maxdepth\" 5\n\
         MakeNamedMedium \"m\" \"string type\" \"homogeneous\" {medium}\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         AttributeBegin\nMediumInterface \"m\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 2\nAttributeEnd\n"
    )
}

#[test]
fn an_absorbing_medium_attenuates_by_beer_lambert() {
    // Every camera ray crosses exactly 2 units of the medium: the image is
    // exp(−2 σₐ) everywhere, with no noise (a medium that does not scatter
    // needs no random distances).
    let sigma = [0.5f32, 1.0, 2.0];
    let m = mean(&inside_sphere("\"rgb sigma_a\" [0.5 1 2] \"rgb sigma_s\" [0 0 0]", 1));
    for c in 0..3 {
        let want = (-2.0 * sigma[c]).exp();
        assert!((m[c] - want).abs() <= 1e-5 * want, "channel {c}: {} vs {want}", m[c]);
    }
    // A shape may name a medium defined further on (pbrt-v4 resolves names
    // after reading the whole file): the same image.
    let text = inside_sphere("\"rgb sigma_a\" [0.5 1 2] \"rgb sigma_s\" [0 0 0]", 1);
    let (head, medium) = text.split_once("MakeNamedMedium").unwrap();
    let (medium, tail) = medium.split_once('\n').unwrap();
    let later = format!("{head}{tail}MakeNamedMedium{medium}\n");
    assert!(later.find("MakeNamedMedium").unwrap() > later.find("Shape").unwrap(), "{later}");
    assert_eq!(mean(&later), m);
    // `scale` multiplies both coefficients.
    let m = mean(&inside_sphere("\"rgb sigma_a\" [0.25 0.5 1] \"rgb sigma_s\" [0 0 0] \"float scale\" 2", 1));
    assert!((m.z - (-4.0f32).exp()).abs() < 1e-6, "{m}");
}

#[test]
fn a_medium_that_only_scatters_keeps_the_furnace_white() {
    // Albedo 1 in every channel, chromatic σₛ and forward scattering: all
    // the light that enters comes out, so under a white environment the
    // sphere of fog is invisible (every pixel converges to 1).
    let text = "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
         Film \"rgb\" \"integer xresolution\" 12 \"integer yresolution\" 12\n\
         Sampler \"independent\" \"integer pixelsamples\" 256\nIntegrator \"volpath\" \"integer maxdepth\" 1000\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0 0 0] \"rgb sigma_s\" [3 1 0.3] \"float g\" 0.6\n\
         AttributeBegin\nMediumInterface \"fog\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n";
    let m = mean(text);
    for c in 0..3 {
        assert!((m[c] - 1.0).abs() < 0.01, "channel {c}: {m}");
    }
    // With absorption it darkens.
    let absorbing = text.replace("\"rgb sigma_a\" [0 0 0]", "\"rgb sigma_a\" [0.5 0.5 0.5]");
    let m = mean(&absorbing);
    assert!(m.max_element() < 0.95, "{m}");
}

#[test]
fn single_scattering_in_a_slab_matches_the_closed_form() {
    // A slab 0 < z < D of medium between two interfaces, lit from above by
    // a distant light of radiance... irradiance E travelling down (−z),
    // seen from below by an orthographic camera looking up (+z). With one
    // scattering event (maxdepth 1) the light reaching the camera is
    //   ∫₀ᴰ σₛ p E e^{−σₜ(D − z)} e^{−σₜ z} dz = D σₛ p E e^{−σₜ D},
    // where p is Henyey–Greenstein for forward scattering,
    // (1 − g²) / (4π (1 − g)³) = (1 + g) / (4π (1 − g)²).
    let (d, g) = (1.5f32, 0.3f32);
    let sigma_s = [0.5f32, 0.2, 1.0];
    let sigma_a = [0.25f32, 0.6, 0.1];
    let text = format!(
        "LookAt 0 0 -1  0 0 1  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.5 0.5 -0.5 0.5]\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
         Sampler \"independent\" \"integer pixelsamples\" 256\nIntegrator \"volpath\" \"integer maxdepth\" 1\n\
         WorldBegin\nLightSource \"distant\" \"point3 from\" [0 0 10] \"point3 to\" [0 0 0] \"rgb L\" [1 1 1]\n\
         MakeNamedMedium \"slab\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [{} {} {}] \"rgb sigma_s\" [{} {} {}] \"float g\" {g}\n\
         Material \"interface\"\n\
         AttributeBegin\nMediumInterface \"\" \"slab\"\nShape \"trianglemesh\" \"point3 P\" [-50 -50 0  50 -50 0  50 50 0  -50 50 0] \"integer indices\" [0 1 2 0 2 3]\nAttributeEnd\n\
         AttributeBegin\nMediumInterface \"slab\" \"\"\nShape \"trianglemesh\" \"point3 P\" [-50 -50 {d}  50 -50 {d}  50 50 {d}  -50 50 {d}] \"integer indices\" [0 1 2 0 2 3]\nAttributeEnd\n",
        sigma_a[0], sigma_a[1], sigma_a[2], sigma_s[0], sigma_s[1], sigma_s[2]
    );
    let m = mean(&text);
    let p = (1.0 + g) / (4.0 * PI * (1.0 - g) * (1.0 - g));
    for c in 0..3 {
        let sigma_t = sigma_a[c] + sigma_s[c];
        let want = d * sigma_s[c] * p * (-sigma_t * d).exp();
        assert!((m[c] - want).abs() < 0.02 * want, "channel {c}: {} vs {want}", m[c]);
    }
}

#[test]
fn glass_with_media_on_both_sides_and_the_camera_medium() {
    // A glass sphere of absorbing "tea" seen through clear air: darker in
    // the channels the tea absorbs; the same sphere without media is clear.
    let scene = |interface: &str| {
        format!(
            "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20\n\
             Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\
             Sampler \"independent\" \"integer pixelsamples\" 64\nIntegrator \"volpath\" \"integer maxdepth\" 20\n\
             WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             MakeNamedMedium \"tea\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.1 1 3] \"rgb sigma_s\" [0 0 0]\n\
             AttributeBegin\n{interface}\nMaterial \"dielectric\" \"float eta\" 1.33\nShape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
        )
    };
    let clear = mean(&scene(""));
    let tea = mean(&scene("MediumInterface \"tea\" \"\""));
    assert!((clear.x - clear.z).abs() < 0.02, "{clear}");
    assert!(tea.x > tea.y && tea.y > tea.z && tea.z < 0.8 * clear.z, "{tea} vs {clear}");
}

#[test]
fn media_errors_and_warnings() {
    let e = import("WorldBegin\nMakeNamedMedium \"m\" \"rgb sigma_a\" [1 1 1]\n").unwrap_err();
    assert!(e.contains("needs a \"string type\""), "{e}");
    let e = import("WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"jelly\"\n").unwrap_err();
    assert!(e.contains("unknown medium type \"jelly\"") && e.contains("homogeneous"), "{e}");
    let e = import("WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [-1 0 0]\n")
        .unwrap_err();
    assert!(e.contains("sigma_a") && e.contains("≥ 0") && e.contains(":2:"), "{e}");
    let e = import("WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float g\" 1\n").unwrap_err();
    assert!(e.contains("asymmetry"), "{e}");
    let e = import("WorldBegin\nMediumInterface \"fog\" \"\"\nShape \"sphere\"\n").unwrap_err();
    assert!(e.contains("medium \"fog\" is not defined") && e.contains(":3:"), "{e}");
    let e = import("MediumInterface \"fog\"\nCamera \"perspective\"\nWorldBegin\n").unwrap_err();
    assert!(e.contains("medium \"fog\" is not defined"), "{e}");
    // Grid media are skipped with a warning (and render as vacuum).
    let s = import("WorldBegin\nMakeNamedMedium \"smoke\" \"string type\" \"nanovdb\" \"string filename\" \"x.nvdb\"\nMediumInterface \"smoke\" \"\"\nShape \"sphere\"\n").unwrap();
    assert!(
        s.scene.warnings().iter().any(|w| w.contains("\"nanovdb\" media are not supported")),
        "{:?}",
        s.scene.warnings()
    );
    assert!(s.scene.media().is_empty());
    // Presets: a measured medium by name; an unknown one warns.
    let s = import("WorldBegin\nMakeNamedMedium \"k\" \"string type\" \"homogeneous\" \"string preset\" \"Ketchup\" \"float scale\" 10\n").unwrap();
    let lucent::medium::Medium::Homogeneous(m) = &s.scene.media()[0];
    assert!((m.sigma_a() - Color::new(0.61, 9.7, 14.5)).abs().max_element() < 1e-4, "{:?}", m.sigma_a());
    let s = import("WorldBegin\nMakeNamedMedium \"k\" \"string type\" \"homogeneous\" \"string preset\" \"Gravy\"\n")
        .unwrap();
    assert!(s.scene.warnings().iter().any(|w| w.contains("unknown preset \"Gravy\"")), "{:?}", s.scene.warnings());
    // The camera's medium is the outside medium at the Camera directive,
    // even when the medium is defined after it.
    let s = import("MediumInterface \"\" \"fog\"\nCamera \"perspective\"\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nWorldBegin\n").unwrap();
    assert_eq!(s.scene.camera_medium(), Some(lucent::medium::MediumId::new(0)));
    // `Attribute "medium"` gives defaults to the media that follow.
    let s = import(
        "WorldBegin\nAttribute \"medium\" \"float scale\" 3\nMakeNamedMedium \"m\" \"string type\" \"homogeneous\"\n",
    )
    .unwrap();
    let lucent::medium::Medium::Homogeneous(m) = &s.scene.media()[0];
    assert_eq!(m.sigma_a(), Color::splat(3.0));
    // pbrt-v4's "path" integrator ignores media; lucent says it renders them.
    let s = import("Integrator \"path\"\nWorldBegin\nMakeNamedMedium \"m\" \"string type\" \"homogeneous\"\n").unwrap();
    assert!(
        s.scene.warnings().iter().any(|w| w.contains("pbrt-v4's \"path\" ignores media")),
        "{:?}",
        s.scene.warnings()
    );
    // AttributeEnd restores the interface.
    let s = import("WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nAttributeBegin\nMediumInterface \"fog\" \"\"\nAttributeEnd\nShape \"sphere\"\n").unwrap();
    assert!(!s.scene.primitives()[0].media().is_transition());
}

/// The TOML form of [`inside_sphere`]: a camera in a sphere of medium.
fn toml_inside_sphere(medium: &str) -> String {
    format!(
        "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, 1]\nfov = 90\nmedium = \"m\"\n\
         [render]\nwidth = 8\nheight = 8\nspp = 1\nintegrator = \"path\"\n\
         [environment]\ncolor = [1, 1, 1]\n\
         [media.m.homogeneous]\n{medium}\n\
         [materials.boundary.interface]\n\
         [[sphere]]\ncenter = [0, 0, 0]\nradius = 2\nmaterial = \"boundary\"\nmedium_inside = \"m\"\n"
    )
}

fn toml(text: &str) -> Result<LoadedScene, String> {
    lucent::loader::parse_scene(text, lucent::loader::SceneFormat::Toml).map_err(|e| e.to_string())
}

#[test]
fn scene_files_describe_media() {
    let s = toml(&toml_inside_sphere("sigma_a = [0.5, 1, 2]\nsigma_s = [0, 0, 0]")).unwrap_or_else(|e| panic!("{e}"));
    let film = render(&s.scene, &s.settings, RenderOptions::default()).unwrap().film;
    for c in film.pixels() {
        assert!((c.x - (-1.0f32).exp()).abs() < 1e-5 && (c.z - (-4.0f32).exp()).abs() < 1e-6, "{c}");
    }
    // A preset, scaled; g and emission.
    let s = toml(&toml_inside_sphere("preset = \"Wholemilk\"\nscale = 0.1\ng = 0.5\nemission = [1, 0, 0]")).unwrap();
    let lucent::medium::Medium::Homogeneous(m) = &s.scene.media()[0];
    assert!((m.sigma_s() - Color::new(0.255, 0.321, 0.377)).abs().max_element() < 1e-6);
    assert_eq!((m.phase().g(), m.le()), (0.5, Color::new(1.0, 0.0, 0.0)));
    // Errors name the key and what is accepted.
    let e = toml(&toml_inside_sphere("preset = \"Gravy\"")).unwrap_err();
    assert!(e.contains("unknown preset \"Gravy\"") && e.contains("Wholemilk") && e.contains(":14:"), "{e}");
    let e = toml(&toml_inside_sphere("preset = \"Wholemilk\"\nsigma_a = [1, 1, 1]")).unwrap_err();
    assert!(e.contains("either `preset` or `sigma_a`"), "{e}");
    let e = toml(&toml_inside_sphere("g = 1.5")).unwrap_err();
    assert!(e.contains("asymmetry"), "{e}");
    let e = toml(&toml_inside_sphere("sigma_a = [1, -1, 1]")).unwrap_err();
    assert!(e.contains("≥ 0"), "{e}");
    let e = toml(&toml_inside_sphere("").replace("medium_inside = \"m\"", "medium_inside = \"fog\"")).unwrap_err();
    assert!(e.contains("medium \"fog\" is not defined under [media] (defined: m)") && e.contains(":20:"), "{e}");
    let e = toml(&toml_inside_sphere("").replace("medium = \"m\"", "medium = \"fog\"")).unwrap_err();
    assert!(e.contains("[camera]: medium \"fog\" is not defined"), "{e}");
}

#[test]
fn media_convert_to_the_same_image() {
    // pbrt-v4 → lucent's format → the same scene: media, the camera's
    // medium, and the media of each surface.
    let text = "MediumInterface \"\" \"air\"\nLookAt 0 0 -1.5  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n\
        Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\
        Sampler \"independent\" \"integer pixelsamples\" 4\nIntegrator \"volpath\" \"integer maxdepth\" 5\n\
        WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
        MakeNamedMedium \"air\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.01 0.02 0.03] \"rgb sigma_s\" [0.05 0.05 0.05] \"float g\" 0.2\n\
        MakeNamedMedium \"tea\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.2 0.5 1] \"rgb sigma_s\" [0.3 0.3 0.3] \"float g\" -0.3\n\
        AttributeBegin\nMediumInterface \"air\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 2\nAttributeEnd\n\
        AttributeBegin\nMediumInterface \"tea\" \"air\"\nMaterial \"dielectric\" \"float eta\" 1.33\nShape \"sphere\" \"float radius\" 0.7\nAttributeEnd\n";
    let a = import(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("converted.toml");
    lucent::loader::export_scene(&a, &out).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.contains("[media.medium-1.homogeneous]") && written.contains("medium_inside"), "{written}");
    let b = lucent::loader::load_scene(&out).unwrap_or_else(|e| panic!("{e}\n{written}"));
    assert_eq!(a.scene.media(), b.scene.media());
    assert_eq!(a.scene.camera_medium(), b.scene.camera_medium());
    let media = |s: &LoadedScene| s.scene.primitives().iter().map(|p| p.media()).collect::<Vec<_>>();
    assert_eq!(media(&a), media(&b));
    let fa = render(&a.scene, &a.settings, RenderOptions::default()).unwrap().film;
    let fb = render(&b.scene, &b.settings, RenderOptions::default()).unwrap().film;
    assert_eq!(fa.pixels(), fb.pixels());
    assert!(fa.pixels().iter().any(|c| c.max_element() > 0.0));
}
