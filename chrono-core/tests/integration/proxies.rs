//! Physics items with collision proxies (spheres, thick triangles) in contact with rigid
//! bodies, through the public API: the proxies rest on the right surface, a particle–body
//! collision conserves linear and angular momentum, a triangle's contact is shared by its
//! nodes through the item's barycentric Jacobian, and bad proxies are rejected.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{BlockId, CcpProblem, MassOperator, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::{ChronoError, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

fn system(gravity: Vector3<f64>) -> System {
    let settings = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 2000,
        record_history: false,
    };
    let sys_settings = SystemSettings {
        gravity,
        ..SystemSettings::default()
    };
    System::new(sys_settings, Box::new(Apgd::new(settings))).unwrap()
}

/// Point masses; as proxies either one sphere each, or one thick triangle on nodes 0,1,2.
struct Particles {
    pos: Vec<Vector3<f64>>,
    vel: Vec<Vector3<f64>>,
    mass: f64,
    radius: f64,
    triangle: bool,
    blocks: Vec<BlockId>,
    material: ContactMaterial,
}

impl Particles {
    fn new(pos: Vec<Vector3<f64>>, mass: f64, radius: f64) -> Self {
        let vel = vec![Vector3::zeros(); pos.len()];
        Self {
            pos,
            vel,
            mass,
            radius,
            triangle: false,
            blocks: Vec::new(),
            material: ContactMaterial::with_friction(0.4),
        }
    }

    /// Barycentric coordinates of `p` (projected) in triangle 0,1,2.
    fn barycentric(&self, p: &Vector3<f64>) -> [f64; 3] {
        let [a, b, c] = [self.pos[0], self.pos[1], self.pos[2]];
        let (e1, e2, d) = (b - a, c - a, p - a);
        let (d11, d12, d22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
        let (d1, d2) = (d.dot(&e1), d.dot(&e2));
        let den = d11 * d22 - d12 * d12;
        let v = (d22 * d1 - d12 * d2) / den;
        let w = (d11 * d2 - d12 * d1) / den;
        [1.0 - v - w, v, w]
    }
}

impl PhysicsItem for Particles {
    fn name(&self) -> &str {
        "particles"
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        self.blocks.clear();
        for _ in &self.pos {
            let m = MassOperator::particle(self.mass).unwrap();
            self.blocks.push(vars.add(m));
        }
    }

    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        for (b, v) in self.blocks.iter().zip(&self.vel) {
            let r = vars.range(*b);
            for d in 0..3 {
                k[r.start + d] += self.mass * (v[d] + ctx.h * ctx.gravity[d]);
            }
        }
    }

    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        if self.triangle {
            out.push(CollisionProxy {
                shape: ProxyShape::Triangle {
                    vertices: [self.pos[0], self.pos[1], self.pos[2]],
                    thickness: self.radius,
                },
                material: self.material,
                id: 0,
            });
        } else {
            for (i, p) in self.pos.iter().enumerate() {
                out.push(CollisionProxy {
                    shape: ProxyShape::Sphere {
                        center: *p,
                        radius: self.radius,
                    },
                    material: self.material,
                    id: i as u32,
                });
            }
        }
    }

    fn proxy_jacobian(
        &self,
        proxy: u32,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        let row = |d: &Vector3<f64>, s: f64| [s * d.x, s * d.y, s * d.z];
        if self.triangle {
            for (node, s) in self.barycentric(p).into_iter().enumerate() {
                let j = dirs.map(|d| row(&d, s));
                entry(self.blocks[node], [&j[0], &j[1], &j[2]]);
            }
        } else {
            let j = dirs.map(|d| row(&d, 1.0));
            entry(self.blocks[proxy as usize], [&j[0], &j[1], &j[2]]);
        }
        [0.0; 3]
    }

    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        _problem: &CcpProblem,
        _gamma: &[f64],
    ) -> chrono_core::Result<()> {
        for ((b, x), u) in self.blocks.iter().zip(&mut self.pos).zip(&mut self.vel) {
            let r = vars.range(*b);
            *u = Vector3::new(v[r.start], v[r.start + 1], v[r.start + 2]);
            *x += ctx.h * *u;
        }
        Ok(())
    }
}

fn particles(sys: &System) -> &Particles {
    sys.item::<Particles>(sys.item_handles().next().unwrap())
        .expect("item 0 is the particles")
}

fn ground(sys: &mut System) {
    let half = Vector3::new(2.0, 2.0, 0.5);
    sys.add_body(
        RigidBodyBuilder::fixed()
            .position(Vector3::new(0.0, 0.0, -0.5))
            .collider(
                Shape::Box { half_extents: half },
                Isometry3::identity(),
                ContactMaterial::with_friction(0.4),
            ),
    )
    .unwrap();
}

#[test]
fn spheres_come_to_rest_on_a_fixed_box() {
    let mut sys = system(GRAVITY);
    ground(&mut sys);
    let r = 0.05;
    let start = vec![
        Vector3::new(0.0, 0.0, 0.3),
        Vector3::new(0.5, 0.2, 0.6),
        Vector3::new(-1.0, 0.7, 0.05),
    ];
    sys.add_item(Box::new(Particles::new(start, 0.1, r)));
    for _ in 0..1000 {
        sys.step(1e-3).unwrap();
    }
    assert_eq!(sys.proxy_contacts().len(), 3);
    for (x, v) in particles(&sys).pos.iter().zip(&particles(&sys).vel) {
        assert!((x.z - r).abs() < 1e-6, "rests at z = {} (radius {r})", x.z);
        assert!(v.norm() < 1e-6, "still moving at {v}");
    }
}

#[test]
fn particle_body_collision_conserves_momentum() {
    // No gravity: a particle flies into a free box off its center line. The impulse exchange
    // conserves linear momentum; without friction the impulse line passes through the
    // particle's center, so angular momentum is conserved too (with friction a point mass,
    // having no spin, cannot take the frictional moment about its center). The box is a
    // cube: with an isotropic inertia `R J w` does not change when the pose is advanced
    // with the new `w`, so the first-order gyroscopic error of the step does not enter.
    for mu in [0.0, 0.5] {
        let mut sys = system(Vector3::zeros());
        let b = Shape::Box {
            half_extents: Vector3::repeat(0.25),
        };
        let bx = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass_from_shape(&b, 500.0)
                    .unwrap()
                    .collider(b, Isometry3::identity(), ContactMaterial::with_friction(mu)),
            )
            .unwrap();
        let mut p = Particles::new(vec![Vector3::new(-1.0, 0.1, 0.07)], 3.0, 0.04);
        p.material = ContactMaterial::with_friction(mu);
        p.vel[0] = Vector3::new(4.0, 0.5, -0.2);
        sys.add_item(Box::new(p));
        let momenta = |sys: &System| {
            let body = sys.body(bx).unwrap();
            let ps = particles(sys);
            let (x, v, m) = (ps.pos[0], ps.vel[0], ps.mass);
            let lin = body.mass() * body.linear_velocity() + m * v;
            let ang = body.angular_momentum()
                + body
                    .position()
                    .cross(&(body.mass() * body.linear_velocity()))
                + x.cross(&(m * v));
            (lin, ang)
        };
        let (l0, a0) = momenta(&sys);
        let mut touched = false;
        for _ in 0..400 {
            sys.step(1e-3).unwrap();
            touched |= !sys.proxy_contacts().is_empty();
        }
        assert!(touched, "mu {mu}: the particle never reached the box");
        let (l1, a1) = momenta(&sys);
        let vb = sys.body(bx).unwrap().linear_velocity();
        assert!(vb.x > 0.1, "mu {mu}: the box was not pushed ({vb})");
        assert!(
            (l1 - l0).norm() < 1e-9 * l0.norm(),
            "mu {mu}: linear {l0} -> {l1}"
        );
        if mu == 0.0 {
            assert!((a1 - a0).norm() < 1e-9 * a0.norm(), "angular {a0} -> {a1}");
        }
    }
}

#[test]
fn triangle_contact_is_shared_by_its_nodes() {
    // A horizontal triangle lands with its centroid on a fixed sphere: the contact point is
    // the centroid, the barycentric weights are 1/3 each, so the nodes stop together at the
    // sphere's top plus the thickness.
    let mut sys = system(GRAVITY);
    let radius = 0.3;
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::Sphere { radius },
        Isometry3::identity(),
        ContactMaterial::with_friction(0.0),
    ))
    .unwrap();
    let z0 = 0.5;
    let nodes = vec![
        Vector3::new(0.4, 0.0, z0),
        Vector3::new(-0.2, 0.35, z0),
        Vector3::new(-0.2, -0.35, z0),
    ];
    let mut tri = Particles::new(nodes, 0.2, 0.01);
    tri.triangle = true;
    sys.add_item(Box::new(tri));
    let mut keys = Vec::new();
    for _ in 0..1000 {
        sys.step(1e-3).unwrap();
        if let Some(c) = sys.proxy_contacts().first() {
            keys.push(c.point.key);
        }
    }
    assert!(keys.len() > 100, "the triangle never touched the sphere");
    assert!(
        keys.windows(2).all(|w| w[0] == w[1]),
        "persistence key changed"
    );
    let ps = particles(&sys);
    for x in &ps.pos {
        assert!((x.z - (radius + 0.01)).abs() < 1e-6, "node at z = {}", x.z);
    }
}

#[test]
fn bad_proxy_is_an_error_naming_item_and_proxy() {
    let mut sys = system(GRAVITY);
    ground(&mut sys);
    sys.add_item(Box::new(Particles::new(
        vec![Vector3::new(0.0, 0.0, 0.1)],
        1.0,
        -0.1,
    )));
    let e = sys.step(1e-3).unwrap_err();
    assert!(matches!(e, ChronoError::InvalidParameter { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.contains("item 0 proxy 0"), "{msg}");
}

/// The SMC stepper does not collide items' proxies: a system with such an item is refused
/// with an error naming the item, before anything moves (it used to let the particles fall
/// through the ground silently).
#[test]
fn smc_refuses_items_with_proxies() {
    let mut sys = system(GRAVITY);
    let mut settings = sys.settings().clone();
    settings.contact_method = chrono_core::ContactMethod::Smc;
    sys.set_settings(settings).unwrap();
    ground(&mut sys);
    sys.add_item(Box::new(Particles::new(
        vec![Vector3::new(0.0, 0.0, 0.1)],
        1.0,
        0.05,
    )));
    let e = sys.step(1e-4).unwrap_err();
    assert!(
        matches!(&e, ChronoError::ItemNotSupported { item, .. } if item == "particles"),
        "{e}"
    );
    assert!(e.to_string().contains("SMC"), "{e}");
    assert_eq!(sys.time(), 0.0);
    assert_eq!(particles(&sys).pos[0].z, 0.1);
}
