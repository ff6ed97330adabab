use super::*;

/// The loading as it was written while it was one enum with struct variants: checkpoints
/// written then must restore now, so the bytes must be the same.
#[derive(Serialize)]
enum Before {
    ElasticModuli(Driven),
    ConfinedCompression(Driven),
    Explosion {
        energy: f64,
        quiet_steps: u64,
        end_time: f64,
        explosive_mass: f64,
        explosive_centre: [f64; 2],
        kicked: usize,
        spent: bool,
    },
    Projectile {
        speed: f64,
        quiet_steps: u64,
        end_time: f64,
        polygon: usize,
        free: bool,
    },
}

fn driven(phase: u8) -> Driven {
    Driven {
        speed: 0.25,
        ramp_time: 1e-4,
        end_strain: 0.01,
        confined: phase == 0,
        bottom: vec![0, 1],
        top: vec![5, 6, 7],
        left: vec![0],
        right: vec![7],
        start: vec![[0.0, 0.5], [1.0, 0.5], [0.0, 2.5], [1.0, 2.5], [2.0, 2.5]],
        length0: 2.0,
        width0: 1.5,
        section: 3e-3,
        sign: -1.0,
        phase,
        phase_start: 2.5e-3,
    }
}

#[test]
fn every_loading_keeps_the_checkpoint_bytes_of_the_variant_it_was() {
    let pairs = [
        (
            Beam2dLoading::ElasticModuli(ElasticModuli { driven: driven(1) }),
            Before::ElasticModuli(driven(1)),
        ),
        (
            Beam2dLoading::ConfinedCompression(ConfinedCompression { driven: driven(0) }),
            Before::ConfinedCompression(driven(0)),
        ),
        (
            Beam2dLoading::Explosion(Explosion {
                energy: 3.5,
                quiet_steps: 300,
                end_time: 1e-3,
                explosive_mass: 2.25e-3,
                explosive_centre: [0.5, -0.25],
                kicked: 6,
                spent: false,
            }),
            Before::Explosion {
                energy: 3.5,
                quiet_steps: 300,
                end_time: 1e-3,
                explosive_mass: 2.25e-3,
                explosive_centre: [0.5, -0.25],
                kicked: 6,
                spent: false,
            },
        ),
        (
            Beam2dLoading::Projectile(Projectile {
                speed: 40.0,
                quiet_steps: 200,
                end_time: 2e-3,
                polygon: 17,
                free: true,
            }),
            Before::Projectile {
                speed: 40.0,
                quiet_steps: 200,
                end_time: 2e-3,
                polygon: 17,
                free: true,
            },
        ),
    ];
    for (now, before) in &pairs {
        let bytes = postcard::to_stdvec(now).expect("encodes");
        assert_eq!(bytes, postcard::to_stdvec(before).expect("encodes"));
        let back: Beam2dLoading = postcard::from_bytes(&bytes).expect("decodes");
        assert_eq!(postcard::to_stdvec(&back).expect("encodes"), bytes);
        assert_eq!(
            serde_json::to_string(now).expect("encodes"),
            serde_json::to_string(before).expect("encodes")
        );
    }
}
