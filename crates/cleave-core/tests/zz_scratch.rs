use cleave_core::curve::Curve;
use cleave_core::mesh::box_model;
use cleave_core::model::*;
use cleave_core::solver::{Observer, Solver};
struct O<F: FnMut(&Solver)>(F);
impl<F: FnMut(&Solver)> Observer for O<F> {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        (self.0)(s);
        Ok(())
    }
}
#[test]
fn scratch() {
    let (len, b) = (0.1, 0.01);
    let (vmax, t_ramp, t_end) = (2.0, 10e-6, 150e-6);
    let mat = Material {
        id: 1,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    };
    let mut m = box_model([40, 4, 4], [len, b, b], mat, t_end);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, t_ramp],
        y: vec![0.0, vmax],
    });
    for node in m.nodes_where(0, 0.0, 1e-9) {
        m.spcs.push(Spc {
            node,
            dof: [true, false, false, false, false, false],
        });
    }
    for node in m.nodes_where(0, len, 1e-9) {
        m.prescribed.push(PrescribedMotion {
            target: MotionTarget::Node(node),
            axis: 0,
            vad: Vad::Velocity,
            curve: 0,
            sf: 1.0,
        });
    }
    let mut wprev = 0.0;
    let mut s = Solver::new(&m).unwrap();
    s.run(&mut O(|s: &Solver| {
        let en = &s.state.energy;
        let w = en.external_work;
        let dw = w - wprev;
        wprev = w;
        let e = en.total();
        if s.state.step % 20 == 0 || s.state.step < 40 && s.state.step % 4 == 0 {
            eprintln!(
                "t {:.3e} step {} E {:.4e} W {:.4e} err {:.3e} err_half {:.3e}",
                s.state.t,
                s.state.step,
                e,
                w,
                (e - w).abs() / w,
                (e - (w - 0.5 * dw)).abs() / w
            );
        }
    }))
    .unwrap();
}
