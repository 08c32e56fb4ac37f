//! The BVHs must find exactly what brute force finds: the same closest hit
//! and the same any-hit answer, on randomized scenes of spheres, planes,
//! triangles, transformed objects and instanced meshes.

use lucent::geometry::{Ray, Transform, Vec3};
use lucent::mesh::TriangleMesh;
use lucent::prelude::*;
use lucent::primitive::{Aggregate, BvhAggregate, LinearAggregate};
use lucent::sampling::Pcg32;
use lucent::shapes::{watertight, Mesh, MeshBvh};
use std::sync::Arc;

fn rand_vec(rng: &mut Pcg32, scale: f32) -> Vec3 {
    Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * scale)
}

fn rand_dir(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = rand_vec(rng, 1.0);
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A random soup of `n` small triangles in a 10-unit cube.
fn soup(rng: &mut Pcg32, n: usize) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for i in 0..n {
        let c = rand_vec(rng, 5.0);
        for _ in 0..3 {
            mesh.positions.push(c + rand_vec(rng, 0.6));
        }
        let k = 3 * i as u32;
        mesh.indices.push([k, k + 1, k + 2]);
    }
    mesh
}

fn random_transform(rng: &mut Pcg32) -> Transform {
    Transform::scale(Vec3::new(0.5 + rng.uniform(), 0.5 + rng.uniform(), 0.5 + rng.uniform()))
        .unwrap()
        .then(&Transform::rotate(rand_dir(rng), rng.uniform() * 360.0).unwrap())
        .then(&Transform::translate(rand_vec(rng, 6.0)))
}

#[test]
fn mesh_bvh_equals_brute_force() {
    let mut rng = Pcg32::new(11, 3);
    for (n, seed) in [(1usize, 1u64), (7, 2), (100, 3), (5000, 4)] {
        let mut rng2 = Pcg32::new(seed, 9);
        let mesh = soup(&mut rng2, n);
        let bvh = MeshBvh::build(&mesh);
        for _ in 0..2000 {
            let ray = Ray::new(rand_vec(&mut rng, 8.0), rand_dir(&mut rng) * (0.1 + 3.0 * rng.uniform()));
            let t_max = if rng.uniform() < 0.3 { 5.0 * rng.uniform() } else { f32::INFINITY };
            let wray = watertight::WatertightRay::new(&ray);
            let mut best: Option<(f32, u32)> = None;
            for i in 0..mesh.triangle_count() {
                // The same per-triangle test the BVH runs, one triangle a block.
                let block = watertight::TriangleBlock::new(&[(mesh.triangle(i), i as u32)]);
                if let Some((_, h)) = watertight::intersect_block(&wray, &block, 0.0, t_max) {
                    if best.is_none_or(|(t, _)| h.t < t) {
                        best = Some((h.t, i as u32));
                    }
                }
            }
            let got = bvh.intersect(&ray, 0.0, t_max).map(|h| (h.t, h.triangle));
            assert_eq!(got.map(|g| g.0), best.map(|b| b.0), "closest t, {n} triangles, ray {ray:?}");
            assert_eq!(bvh.occluded(&ray, 0.0, t_max), best.is_some(), "any hit, {n} triangles");
        }
    }
}

/// A random scene: spheres, triangles, planes, transformed ones and
/// instances of two meshes.
fn random_primitives(rng: &mut Pcg32, material: MaterialId) -> Vec<Primitive> {
    let meshes: Vec<Arc<Mesh>> = (0..2).map(|_| Arc::new(Mesh::new(soup(rng, 50)).unwrap())).collect();
    let mut prims = Vec::new();
    for i in 0..60 {
        let t = if rng.uniform() < 0.5 { random_transform(rng) } else { Transform::IDENTITY };
        let prim = match i % 4 {
            0 => Primitive::new(Sphere::new(rand_vec(rng, 6.0), 0.2 + rng.uniform()).unwrap(), t, material),
            1 => {
                let c = rand_vec(rng, 6.0);
                let tri = Triangle::new([c + rand_vec(rng, 1.0), c + rand_vec(rng, 1.0), c + rand_vec(rng, 1.0)], None);
                match tri {
                    Ok(tri) => Primitive::new(tri, t, material),
                    Err(_) => continue,
                }
            }
            2 => Primitive::new(lucent::shapes::Shape::Mesh(meshes[i % 2].clone()), random_transform(rng), material),
            _ if i % 20 == 3 => Primitive::new(Plane::new(rand_vec(rng, 9.0), rand_dir(rng)).unwrap(), t, material),
            _ => Primitive::new(Sphere::new(Vec3::ZERO, 0.5).unwrap(), random_transform(rng), material),
        };
        prims.push(prim);
    }
    prims
}

#[test]
fn scene_bvh_equals_brute_force() {
    let mut rng = Pcg32::new(5, 5);
    let camera = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 4, 4).unwrap();
    let mut scene = SceneBuilder::new(camera);
    let m = scene.add_material(Material::matte(Color::ONE, 1.0).unwrap()).unwrap();
    for round in 0..4 {
        let prims = random_primitives(&mut rng, m);
        let bvh = BvhAggregate::new(&prims);
        let list = LinearAggregate::new(prims);
        for _ in 0..3000 {
            let ray = Ray::new(rand_vec(&mut rng, 10.0), rand_dir(&mut rng) * (0.2 + 2.0 * rng.uniform()));
            let t_max = if rng.uniform() < 0.3 { 8.0 * rng.uniform() } else { f32::INFINITY };
            let a = bvh.intersect(&ray, t_max);
            let b = list.intersect(&ray, t_max);
            assert_eq!(a.map(|h| h.t), b.map(|h| h.t), "closest hit differs (round {round}, ray {ray:?})");
            if let (Some(a), Some(b)) = (a, b) {
                assert_eq!(a.p, b.p);
                assert_eq!(a.n, b.n);
            }
            assert_eq!(bvh.intersect_p(&ray, t_max), list.intersect_p(&ray, t_max), "any hit differs");
        }
    }
}

/// Scenes of a handful of primitives: their top-level tree is often a
/// single node, which is traversed without a stack (one box test, the hit
/// leaves in slot order). Both queries must still match brute force, and
/// the one-node case must actually occur.
#[test]
fn small_scene_bvh_equals_brute_force() {
    let mut rng = Pcg32::new(17, 2);
    let camera = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 4, 4).unwrap();
    let mut scene = SceneBuilder::new(camera);
    let m = scene.add_material(Material::matte(Color::ONE, 1.0).unwrap()).unwrap();
    let mut one_node = 0;
    for count in 1..=12 {
        let all = random_primitives(&mut rng, m);
        let prims: Vec<Primitive> = all.into_iter().take(count).collect();
        let bvh = BvhAggregate::new(&prims);
        let bounded: Vec<_> = prims.iter().filter(|p| !p.bounds().is_infinite()).map(|p| p.bounds()).collect();
        one_node += (lucent::accel::Bvh::build(&bounded).nodes().len() == 1) as u32;
        let list = LinearAggregate::new(prims);
        for _ in 0..2000 {
            let ray = Ray::new(rand_vec(&mut rng, 10.0), rand_dir(&mut rng) * (0.2 + 2.0 * rng.uniform()));
            let t_max = if rng.uniform() < 0.3 { 8.0 * rng.uniform() } else { f32::INFINITY };
            let (a, b) = (bvh.intersect(&ray, t_max), list.intersect(&ray, t_max));
            assert_eq!(a.map(|h| h.t), b.map(|h| h.t), "closest hit differs ({count} primitives, ray {ray:?})");
            if let (Some(a), Some(b)) = (a, b) {
                assert_eq!((a.p, a.n), (b.p, b.n));
            }
            assert_eq!(bvh.intersect_p(&ray, t_max), list.intersect_p(&ray, t_max), "any hit differs ({count})");
        }
    }
    assert!(one_node >= 6, "only {one_node} of 12 small scenes had a one-node tree");
}

#[test]
fn instances_render_like_copies() {
    // One mesh placed three times with transforms, against three meshes
    // whose vertices were transformed into the world beforehand.
    let mut rng = Pcg32::new(21, 0);
    let base = soup(&mut rng, 200);
    let transforms: Vec<Transform> = (0..3).map(|_| random_transform(&mut rng)).collect();
    let camera = Camera::new(Vec3::new(0.0, 0.0, -25.0), Vec3::ZERO, Vec3::Y, 50.0, 48, 48).unwrap();
    let build = |instanced: bool| {
        let mut scene = SceneBuilder::new(camera.clone());
        let settings = RenderSettings { spp: 4, ..RenderSettings::default() };
        scene.set_ambient(Color::splat(0.1)).unwrap();
        let m = scene.add_material(Material::matte(Color::new(0.8, 0.6, 0.4), 1.0).unwrap()).unwrap();
        scene.add_light(Light::directional(Vec3::new(0.3, -1.0, 0.5), Color::ONE, 1.0).unwrap());
        let shared = Arc::new(Mesh::new(base.clone()).unwrap());
        for t in &transforms {
            if instanced {
                scene.add_shape(lucent::shapes::Shape::Mesh(shared.clone()), *t, m).unwrap();
            } else {
                let mut copy = base.clone();
                for p in &mut copy.positions {
                    *p = t.point(*p);
                }
                let copy = lucent::shapes::Shape::Mesh(Arc::new(Mesh::new(copy).unwrap()));
                scene.add_shape(copy, Transform::IDENTITY, m).unwrap();
            }
        }
        render(&scene.build().unwrap(), &settings, RenderOptions::default()).unwrap().film
    };
    let (a, b) = (build(true), build(false));
    let mut differing = 0;
    for (x, y) in a.pixels().iter().zip(b.pixels()) {
        let d = (*x - *y).abs().max_element();
        if d > 1e-3 {
            differing += 1;
        }
    }
    // Only pixels where a sample grazes an edge may differ (the two differ in
    // the last bits of every vertex).
    assert!(differing <= a.pixels().len() / 100, "{differing} pixels differ");
    assert!(a.pixels().iter().any(|c| c.max_element() > 0.2), "the meshes must be visible");
}
