//! The lights' constructors: what they accept, what they make exact, and the field each refusal
//! names.

use glam::{DVec2, DVec3};

use crate::{DistantLight, LightError, RectLight};

#[test]
fn a_rectangle_light_names_the_field_it_refuses() {
    let ok = |c, n, t, s| RectLight::new(c, n, t, s);
    let (c, n, t, s) = (DVec3::Y * 4.0, DVec3::NEG_Y, DVec3::X, DVec2::ONE);
    assert!(ok(c, n, t, s).is_ok());
    let cases: [(Result<RectLight, LightError>, &str); 7] = [
        (ok(DVec3::new(f64::NAN, 0.0, 0.0), n, t, s), "center"),
        (ok(DVec3::splat(1e16), n, t, s), "center"),
        (ok(c, DVec3::ZERO, t, s), "normal"),
        (ok(c, DVec3::new(0.0, -2.0, 0.0), t, s), "normal"),
        (
            ok(c, n, DVec3::new(1.0, 1.0, 0.0).normalize(), s),
            "tangent",
        ),
        (ok(c, n, t, DVec2::new(1.0, 0.0)), "size"),
        (ok(c, n, t, DVec2::new(f64::INFINITY, 1.0)), "size"),
    ];
    for (result, field) in cases {
        let e = result.expect_err(field);
        assert!(e.to_string().starts_with(field), "{field}: {e}");
    }
    // Merely not unit length: the message gives the unit vector to write.
    let e = ok(c, DVec3::new(1.0, 2.0, 0.5), t, s).unwrap_err();
    let LightError::NotUnit { normalized, .. } = e else {
        panic!("{e:?}")
    };
    assert!((normalized - DVec3::new(1.0, 2.0, 0.5).normalize()).length() < 1e-15);
    assert!(
        e.to_string()
            .contains(&format!("normalised it is {normalized}"))
    );
}

#[test]
fn values_within_the_tolerance_are_made_exact() {
    let l = RectLight::new(
        DVec3::ZERO,
        DVec3::new(0.0, -1.00005, 0.0),
        DVec3::new(1.0, 0.00005, 0.0),
        DVec2::ONE,
    )
    .unwrap();
    assert_eq!(l.normal, DVec3::NEG_Y);
    assert!((l.tangent.length() - 1.0).abs() < 1e-15 && l.tangent.dot(l.normal).abs() < 1e-15);
    assert_eq!(l.bitangent, l.normal.cross(l.tangent));
}

#[test]
fn an_aimed_light_faces_its_target_with_a_horizontal_first_side() {
    let size = DVec2::new(1.2, 0.6);
    // Down from a ceiling, and straight up: the first side along x.
    for (target, normal) in [(DVec3::ZERO, DVec3::NEG_Y), (DVec3::Y * 9.0, DVec3::Y)] {
        let l = RectLight::aimed(DVec3::Y * 3.0, target, size).unwrap();
        assert_eq!((l.normal, l.tangent, l.size), (normal, DVec3::X, size));
    }
    // Tilted: the normal towards the target, the tangent horizontal and orthogonal to it.
    let (center, target) = (DVec3::new(2.0, 3.0, 1.0), DVec3::new(-1.0, 0.0, 0.5));
    let l = RectLight::aimed(center, target, size).unwrap();
    assert!((l.normal - (target - center).normalize()).length() < 1e-15);
    assert!(l.tangent.y.abs() < 1e-15 && l.tangent.dot(l.normal).abs() < 1e-15);
    assert!(l.is_lit_side(target));
    assert!(matches!(
        RectLight::aimed(center, center, size),
        Err(LightError::TargetAtCenter { .. })
    ));
    assert!(matches!(
        RectLight::aimed(center, DVec3::new(0.0, f64::NAN, 0.0), size),
        Err(LightError::NotFinite {
            field: "target",
            ..
        })
    ));
}

#[test]
fn the_sun_s_angles_follow_the_compass() {
    let dir = |az: f64, el: f64| DistantLight::sun(az, el, 0.53).unwrap().direction;
    let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
    // North is -z, east +x, south +z, west -x; up is +y.
    assert!(close(dir(0.0, 0.0), DVec3::NEG_Z));
    assert!(close(dir(90.0, 0.0), DVec3::X));
    assert!(close(dir(180.0, 0.0), DVec3::Z));
    assert!(close(dir(270.0, 0.0), DVec3::NEG_X));
    assert!(close(dir(-90.0, 0.0), DVec3::NEG_X));
    assert!(close(dir(45.0, 90.0), DVec3::Y));
    let (c, s) = (60f64.to_radians().cos(), 60f64.to_radians().sin());
    assert!(close(dir(0.0, 60.0), DVec3::new(0.0, s, -c)));
    // The tangent is horizontal, east at the zenith; the angles are the light's.
    let sun = DistantLight::sun(200.0, 25.0, 0.53).unwrap();
    assert!(sun.tangent.y.abs() < 1e-15 && sun.tangent.dot(sun.direction).abs() < 1e-15);
    assert_eq!(sun.angular_size_deg, DVec2::splat(0.53));
    assert!(close(
        DistantLight::sun(0.0, 90.0, 1.0).unwrap().tangent,
        DVec3::X
    ));
    // Another north and up: +z up, +y north.
    let z_up = DistantLight::sun_in(DVec3::Y, DVec3::Z, 90.0, 0.0, DVec2::ONE).unwrap();
    assert!(close(z_up.direction, DVec3::Y.cross(DVec3::Z)));
    for (az, el, field) in [
        (0.0, 90.5, "elevation_deg"),
        (0.0, f64::NAN, "elevation_deg"),
        (f64::INFINITY, 10.0, "azimuth_deg"),
    ] {
        let e = DistantLight::sun(az, el, 0.53).unwrap_err();
        assert!(
            matches!(e, LightError::Angle { field: f, .. } if f == field),
            "{e}"
        );
    }
    assert!(matches!(
        DistantLight::sun(0.0, 10.0, 0.0),
        Err(LightError::AngularSize { .. })
    ));
    assert!(matches!(
        DistantLight::sun_in(DVec3::Y, DVec3::Y, 0.0, 10.0, DVec2::ONE),
        Err(LightError::SunFrame { .. })
    ));
}

#[test]
fn a_distant_light_names_the_field_it_refuses() {
    let t = DVec3::X;
    let a = DVec2::splat(0.53);
    let e = DistantLight::new(DVec3::new(0.0, 2.0, 0.0), t, a).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("direction [0, 2, 0] is not unit length"),
        "{e}"
    );
    assert!(e.to_string().contains("normalised it is [0, 1, 0]"), "{e}");
    let e = DistantLight::new(DVec3::Y, DVec3::Y, a).unwrap_err();
    assert!(e.to_string().contains("not orthogonal to direction"), "{e}");
    let e = DistantLight::new(DVec3::Y, t, DVec2::new(0.5, 91.0)).unwrap_err();
    assert!(e.to_string().starts_with("angular_size"), "{e}");
}
