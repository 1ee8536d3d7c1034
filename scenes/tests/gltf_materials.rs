//! glTF materials and textures: metallic-roughness factors × textures, sRGB vs linear
//! decoding, sampler wrap modes, the default material, emission (KHR_materials_emissive_strength),
//! external and embedded images, and notes about ignored features.

mod gltf_support;

use glam::{Vec3, Vec4};
use gltf_support::*;
use scenes::{Emission, Material, Scattering, TexRgb, TexScalar, WrapMode};

/// Exact sRGB decode, written out independently of the crate (IEC 61966-2-1).
fn srgb(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn metal_rough_factors_textures_and_samplers() {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let base_png = data_uri(
        "image/png",
        &png(2, 1, &[[188, 0, 255, 128], [255, 255, 255, 255]]),
    );
    let mr_png = data_uri("image/png", &png(1, 1, &[[0, 128, 64, 255]]));
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],\
         \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorFactor\":[0.5,0.25,1,1],\"baseColorTexture\":{{\"index\":0}},\
            \"metallicFactor\":0.7,\"roughnessFactor\":0.9,\"metallicRoughnessTexture\":{{\"index\":1}}}}}}],\
         \"samplers\":[{{\"wrapS\":33071,\"wrapT\":33648}}],\
         \"textures\":[{{\"source\":0,\"sampler\":0}},{{\"source\":1}}],\
         \"images\":[{{\"uri\":\"{base_png}\"}},{{\"uri\":\"{mr_png}\"}}]"
    );
    let scene = load_json("metal-rough", &document(&bin.parts(), &rest)).unwrap();
    let Material::MetalRough {
        base_color,
        metallic,
        roughness,
        ..
    } = &scene.materials[scene.shapes[0].material]
    else {
        panic!("expected MetalRough, got {:?}", scene.materials);
    };
    let TexRgb::Image { texture: bt, factor } = base_color else {
        panic!("{base_color:?}")
    };
    assert_eq!(*factor, Vec3::new(0.5, 0.25, 1.0));
    let tex = &scene.textures[*bt];
    assert_eq!((tex.width, tex.height), (2, 1));
    assert_eq!(tex.wrap, [WrapMode::Clamp, WrapMode::Mirror]);
    let want = Vec4::new(srgb(188), 0.0, 1.0, 128.0 / 255.0);
    assert!(
        (tex.texels[0] - want).abs().max_element() < 1e-6,
        "sRGB texel: expected {want}, got {}",
        tex.texels[0]
    );
    assert_eq!(
        *metallic,
        TexScalar::Image {
            texture: bt + 1,
            channel: 2,
            factor: 0.7
        },
        "metallic = B channel × factor"
    );
    assert_eq!(
        *roughness,
        TexScalar::Image {
            texture: bt + 1,
            channel: 1,
            factor: 0.9
        }
    );
    let mr = &scene.textures[bt + 1];
    assert_eq!(
        mr.wrap,
        [WrapMode::Repeat, WrapMode::Repeat],
        "glTF's default sampler repeats"
    );
    assert_eq!(
        mr.texels[0],
        Vec4::new(0.0, 128.0 / 255.0, 64.0 / 255.0, 1.0),
        "data textures stay linear"
    );
    assert_eq!(mesh(&scene, "tri/0").uvs.len(), 3);
}

#[test]
fn default_material_is_the_gltf_default() {
    let mut bin = Bin::new();
    let meshes = triangle(&mut bin, "", None);
    let scene = load_json(
        "default-material",
        &document(&bin.parts(), &format!("{meshes},\"nodes\":[{{\"mesh\":0}}]")),
    )
    .unwrap();
    assert_eq!(
        scene.materials,
        vec![Material::MetalRough {
            base_color: TexRgb::Constant(Vec3::ONE),
            metallic: TexScalar::Constant(1.0),
            roughness: TexScalar::Constant(1.0),
            scattering: Scattering::Single,
        }]
    );
    assert!(scene.shapes[0].emission.is_none() && scene.shapes[0].normal_map.is_none());
}

#[test]
fn emission_is_factor_times_texture_times_strength_one_sided() {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let pos = bin.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let img = data_uri("image/png", &png(1, 1, &[[255, 188, 0, 255]]));
    let rest = format!(
        "\"meshes\":[{{\"name\":\"glow\",\"primitives\":[\
            {{\"attributes\":{{\"POSITION\":{pos}}},\"material\":0}},\
            {{\"attributes\":{{\"POSITION\":{pos},\"TEXCOORD_0\":{uv}}},\"material\":1}}]}}],\
         \"nodes\":[{{\"mesh\":0}}],\"extensionsUsed\":[\"KHR_materials_emissive_strength\"],\
         \"materials\":[\
            {{\"emissiveFactor\":[1,0.5,0.25],\"extensions\":{{\"KHR_materials_emissive_strength\":{{\"emissiveStrength\":4}}}}}},\
            {{\"emissiveFactor\":[1,1,0.5],\"emissiveTexture\":{{\"index\":0}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{img}\"}}]"
    );
    let scene = load_json("emission", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(
        scene.shapes[0].emission,
        Some(Emission {
            radiance: TexRgb::Constant(Vec3::new(4.0, 2.0, 1.0)),
            two_sided: false
        })
    );
    let Some(Emission {
        radiance: TexRgb::Image { texture, factor },
        two_sided: false,
    }) = &scene.shapes[1].emission
    else {
        panic!("{:?}", scene.shapes[1].emission);
    };
    assert_eq!(*factor, Vec3::new(1.0, 1.0, 0.5));
    let got = scene.textures[*texture].texels[0];
    assert!(
        (got.y - srgb(188)).abs() < 1e-6,
        "emissive texture is sRGB: expected {}, got {}",
        srgb(188),
        got.y
    );
    assert_eq!(
        scene.light_names(),
        ["glow/0", "glow/1"],
        "emissive primitives are area lights"
    );
}

#[test]
fn textures_are_shared_per_colour_space() {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let img = data_uri("image/png", &png(1, 1, &[[188, 188, 188, 255]]));
    // Texture 0 used as base colour (sRGB) by both materials and as normal map (linear).
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],\
         \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0}}}},\"normalTexture\":{{\"index\":0}}}},\
                        {{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0}}}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{img}\"}}]"
    );
    let scene = load_json("shared-textures", &document(&bin.parts(), &rest)).unwrap();
    assert_eq!(
        scene.textures.len(),
        2,
        "one sRGB and one linear decoding of the same image"
    );
    let linear = scene.shapes[0].normal_map.as_ref().unwrap().texture;
    assert!((scene.textures[linear].texels[0].x - 188.0 / 255.0).abs() < 1e-6);
}

#[test]
fn external_buffer_and_image_files_and_glb_embedded_image() {
    let dir = temp_dir("external");
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let meshes = triangle(&mut bin, &format!(",\"TEXCOORD_0\":{uv}"), Some(0));
    let png_bytes = png(1, 1, &[[0, 255, 0, 255]]);
    write(&dir, "geo metry.bin", &bin.bytes);
    write(&dir, "green.png", &png_bytes);
    let material = "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],\"textures\":[{\"source\":0}]";
    let rest =
        format!("{meshes},\"nodes\":[{{\"mesh\":0}}],{material},\"images\":[{{\"uri\":\"green.png\"}}]");
    // The buffer URI is percent-encoded (glTF URIs follow RFC 3986).
    let path = write(
        &dir,
        "external.gltf",
        document(&bin.parts_with_uri("geo%20metry.bin"), &rest),
    );
    let scene = scenes::gltf::load(&path).unwrap();
    assert_eq!(scene.textures[0].texels[0], Vec4::new(0.0, 1.0, 0.0, 1.0));
    assert_eq!(mesh(&scene, "tri/0").positions.len(), 3);

    // The same asset as a GLB with the image in a buffer view of the BIN chunk.
    let img_view = bin.view(&png_bytes, None);
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],{material},\"images\":[{{\"bufferView\":{img_view},\"mimeType\":\"image/png\"}}]"
    );
    let json = document(&bin.parts_with_uri(""), &rest);
    let path = write(&dir, "packed.glb", glb(&json, &bin.bytes));
    let scene = scenes::load(&path).unwrap();
    assert_eq!(scene.textures[0].texels[0], Vec4::new(0.0, 1.0, 0.0, 1.0));
}

#[test]
fn ignored_features_are_reported_as_notes() {
    let mut bin = Bin::new();
    let uv = bin.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let col = bin.vec4(&[[1.0, 0.0, 0.0, 1.0]; 3]);
    let meshes = triangle(
        &mut bin,
        &format!(",\"TEXCOORD_0\":{uv},\"COLOR_0\":{col}"),
        Some(0),
    );
    let img = data_uri("image/png", &png(1, 1, &[[255, 255, 255, 255]]));
    let rest = format!(
        "{meshes},\"nodes\":[{{\"mesh\":0}}],\"extensionsUsed\":[\"KHR_texture_transform\"],\
         \"materials\":[{{\"alphaMode\":\"BLEND\",\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":0,\
            \"extensions\":{{\"KHR_texture_transform\":{{\"scale\":[2,2]}}}}}}}}}}],\
         \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"{img}\"}}]"
    );
    let dir = temp_dir("notes");
    let loaded =
        scenes::gltf::load_with_notes(&write(&dir, "notes.gltf", document(&bin.parts(), &rest))).unwrap();
    let all = loaded.notes.join("\n");
    for want in ["KHR_texture_transform", "materials[0].alphaMode", "COLOR_0"] {
        assert!(all.contains(want), "notes should mention {want}:\n{all}");
    }
}
