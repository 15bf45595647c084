//! The stepped greedy policy executes what the recursive greedy episode executes.

use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use usar_maxq::maxq::{Domain, Hierarchy};
use usar_maxq::taxi::{Taxi, TaxiConfig, TaxiHierarchy, random_start};
use usar_maxq::{Delegation, GreedyStepper, MaxqQ, Next};

/// Records the actions a domain was asked to execute.
struct Recording(Vec<usize>);

impl Domain for Recording {
    type State = usar_maxq::taxi::TaxiState;
    fn step(&mut self, s: &Self::State, action: usize) -> (Self::State, f64) {
        self.0.push(action);
        Taxi.step(s, action)
    }
    fn is_terminal(&self, s: &Self::State) -> bool {
        Taxi.is_terminal(s)
    }
}

fn trained(episodes: u32) -> (TaxiHierarchy, MaxqQ) {
    let h = TaxiHierarchy::default();
    let mut q = MaxqQ::new(h.nodes().to_vec(), TaxiConfig::default().params);
    let mut rng = Pcg64Mcg::seed_from_u64(7);
    for _ in 0..episodes {
        let s0 = random_start(&mut rng);
        q.learn_episode(&h, &mut Taxi, s0, &mut rng);
    }
    (h, q)
}

#[test]
fn stepping_the_greedy_policy_gives_the_greedy_episodes_actions() {
    // Half-trained and trained: the policies differ, the stepping must follow each.
    for episodes in [50, 2_000] {
        let (h, q) = trained(episodes);
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        for _ in 0..40 {
            let s0 = random_start(&mut rng);
            let mut recorded = Recording(Vec::new());
            let episode = q.greedy_episode(&h, &mut recorded, s0);
            let mut stepper =
                GreedyStepper::new(TaxiConfig::default().params.max_steps_per_episode);
            let (mut s, mut stepped, mut reward) = (s0, Vec::new(), 0.0);
            loop {
                match stepper.next(&q, &h, &s, Taxi.is_terminal(&s), |_, _| Delegation::Learner) {
                    Next::Act(a) => {
                        stepped.push(a);
                        let (n, r) = Taxi.step(&s, a);
                        s = n;
                        reward += r;
                    }
                    Next::Wait => panic!("nobody was asked"),
                    Next::Finished => break,
                }
            }
            assert_eq!(stepped, recorded.0, "{episodes} episodes, start {s0:?}");
            assert_eq!(reward, episode.reward);
        }
    }
}

#[test]
fn a_pending_delegation_waits_and_its_answer_is_obeyed() {
    let (h, q) = trained(2_000);
    let s0 = random_start(&mut Pcg64Mcg::seed_from_u64(3));
    let mut stepper = GreedyStepper::new(100);
    let mut asked = 0;
    for _ in 0..2 {
        let next = stepper.next(&q, &h, &s0, false, |node, _| {
            if node == 0 {
                asked += 1;
                Delegation::Pending
            } else {
                Delegation::Learner
            }
        });
        assert_eq!(next, Next::Wait);
    }
    assert_eq!(asked, 2);
    // The answer arrives: the root's first child (Get) is entered and a primitive follows.
    let next = stepper.next(&q, &h, &s0, false, |node, _| {
        if node == 0 {
            Delegation::Child(0)
        } else {
            Delegation::Learner
        }
    });
    assert!(matches!(next, Next::Act(_)));
    assert_eq!(stepper.active().take(2).collect::<Vec<_>>()[..2], [0, 1]);
}
