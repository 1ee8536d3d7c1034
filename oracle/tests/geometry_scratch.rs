mod geometry_util;
use glam::Vec3;
use oracle::geometry::{Accel, Ray};
#[test]
fn scratch() {
    let sc = geometry_util::scene(vec![geometry_util::shape("s", scenes::Geometry::Sphere { center: Vec3::ZERO, radius: 2.0 })]);
    let a = Accel::build(&sc).unwrap();
    eprintln!("{a:?}");
    eprintln!("{:?}", a.intersect(&Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X), f32::INFINITY));
    eprintln!("{:?}", a.occluded(&Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X), f32::INFINITY));
    eprintln!("{:?}", a.intersect(&Ray::new(Vec3::new(5.0, 0.1, 0.1), -Vec3::X), f32::INFINITY));
}
