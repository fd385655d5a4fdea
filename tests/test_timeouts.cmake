# Each Catch2 test case's CTest TIMEOUT in seconds: max(30, 5 x its measured wall time), rounded up to
# 10 s. Written by tests/measure_timeouts.py from a run of the whole suite (ctest -j2, 2 shared cores);
# rerun it after adding slow tests. Cases not listed get their tier's limit (tests/CMakeLists.txt).
aggkit_test_timeout([==[2-D periodic run to one cluster: no overlap, momentum conserved, energy never grows]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[2-D reflecting run to one cluster: momentum plus wall impulse conserved]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[3-D periodic and reflecting runs to one cluster]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[3-D: two spheres merge head-on]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[BDF steps grow in a steady state next to a stable focus (stability limit detection)]==] 110)  # measured 21.1 s
aggkit_test_timeout([==[DAHA: 200 random collisions of a disc with a cluster converge]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[DAHA: a fixed partner holds and a periodic shift is honoured]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[DAHA: three discs, a chain and a triangle, touch along every link without overlap]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[DAHA: two overlapping linked discs end touching]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[E[R^3] by GSL quadrature agrees with a Monte Carlo mean]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[Hopf normal form: a supercritical bifurcation whose predicted cycle is the one shot from the flow]==] 30)  # measured 5.1 s
aggkit_test_timeout([==[K = 2 with shattering: n1 = λ/(1+λ) and M0 = 2λ/(1+2λ)]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[K = 2, lambda = 0.1: the logistic M0 is met in proportion to rtol]==] 110)  # measured 20.5 s
aggkit_test_timeout([==[K = 2, lambda = 0: moment errors fall in proportion to rtol]==] 100)  # measured 18.4 s
aggkit_test_timeout([==[K = 2, lambda = 0: the dense-Jacobian BDF is proportional too]==] 30)  # measured 1.1 s
aggkit_test_timeout([==[K = 2, lambda = 0: the far tail stays empty at early times]==] 30)  # measured 0.5 s
aggkit_test_timeout([==[Krylov eigenvalues match the dense ones]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[PETSc options change the solve: -snes_rtol stops earlier, the command line overrides the scene]==] 30)  # measured 1.1 s
aggkit_test_timeout([==[Poincare section: the cubic crossing and state of a known curve]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[RSA fills periodic boxes on the minimum image and reflecting boxes inside the walls]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[RSA places N particles without overlap inside cubes and spheres in open space]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[RSA reaches 0.3 in 2-D and gives up at 0.7]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[SNES agrees with a long CVODE run]==] 30)  # measured 4.4 s
aggkit_test_timeout([==[a = 0.95, λ = 0.01 is unstable (Hopf) and a = 0.9, λ = 0.01 stable]==] 80)  # measured 14.3 s
aggkit_test_timeout([==[a branch's root at lambda does not depend on what was asked before]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[a cloud denser than RSA can place is an InputError naming the fraction]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[a cluster is reflected as a whole when one member touches the wall]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[a density mass law gives m = 4/3 pi rho R^3 (pi rho R^2 in 2-D)]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[a discretisation's dense Jacobian is its exact J·v and its leak gradient that of its leak rate]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[a start file round-trips a written start]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[a start that is another lambda's root is not accepted: Newton balances the root's own rates]==] 30)  # measured 4.3 s
aggkit_test_timeout([==[a steady branch refuses a bad anchor, step or lambda]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[a truncated normal has the moments of the truncated density]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[active range: README example agrees with the full range]==] 70)  # measured 13.6 s
aggkit_test_timeout([==[active range: constant kernel with exact moments, adaptive = full range = exact]==] 50)  # measured 9.3 s
aggkit_test_timeout([==[an open boundary has no box: no sides needed, positions left as they are]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[an unknown method or ERK table is refused naming the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[auto hands the stiff ballistic run over to BDF and meets its tolerance]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[auto stays explicit where the run is not stiff]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[bad boxes and boundary names are InputErrors]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[bad kernel input names the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[bad laws name the entry, the value and what is allowed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ballistic low-rank approximation meets the requested tolerance]==] 40)  # measured 6.0 s
aggkit_test_timeout([==[ballistic2d: the kinetic-theory rate of Maxwellian discs, by Monte Carlo and in its limits]==] 30)  # measured 0.6 s
aggkit_test_timeout([==[bench figures: rows accumulate under one header, quoted where needed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[box side from the volume fraction and back]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cell lists insert, move and remove]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cells are at least the contact distance and about the wanted number]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[checkpoint cli: CVODE continues within its integration tolerance after SIGKILL and SIGTERM]==] 30)  # measured 3.0 s
aggkit_test_timeout([==[checkpoint cli: DEM with gravity and friction continues bit for bit after SIGKILL and SIGTERM]==] 30)  # measured 4.7 s
aggkit_test_timeout([==[checkpoint cli: DSMC (both methods) continues bit for bit after SIGKILL and SIGTERM]==] 30)  # measured 2.3 s
aggkit_test_timeout([==[checkpoint cli: ED continues bit for bit after SIGKILL and SIGTERM]==] 30)  # measured 2.9 s
aggkit_test_timeout([==[checkpoint cli: TS continues bit for bit after SIGKILL and SIGTERM]==] 30)  # measured 1.2 s
aggkit_test_timeout([==[checkpoint cli: damaged, truncated and changed-scene checkpoints are refused with exit 2]==] 30)  # measured 2.7 s
aggkit_test_timeout([==[checkpoint: a file is written atomically and read back whole]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[checkpoint: a state is read back value for value, and its end is checked]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[checkpoint: damaged, truncated, grown, foreign and mismatched files are refused with the reason]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[checkpoint: the fingerprint is FNV-1a 64]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[child process: a program that cannot start says so when finished]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[child process: a started process never finished is killed and reaped]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[child process: a started process reads its input when finished]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[child process: input to a child that already exited is no SIGPIPE]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[child process: the started plot command runs a script with the arguments it is sent]==] 40)  # measured 7.4 s
aggkit_test_timeout([==[cli: --version, kernels and command-line errors]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[cli: PETSc options after -- reach the snes engine, bad ones exit 2]==] 50)  # measured 9.2 s
aggkit_test_timeout([==[cli: a missing or unreadable scene exits 2 naming the path]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[cli: a plotter that cannot run is a warning, not a failure]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[cli: a run refused for bad input leaves no summary of the earlier run in its folder]==] 30)  # measured 0.6 s
aggkit_test_timeout([==[cli: a scene name that looks like an option still gets its plot]==] 40)  # measured 6.3 s
aggkit_test_timeout([==[cli: a scene nested 40000 levels deep or an endless file is refused, not a crash]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[cli: an impossible tolerance exits 1 and says FAIL]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[cli: an output folder that cannot be created exits 2 before running]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[cli: bad input exits 2 naming the key and value, and leaves no outputs]==] 60)  # measured 11.5 s
aggkit_test_timeout([==[cli: input that once crashed, hung or printed nonsense exits 2 naming the key, in bounded time]==] 130)  # measured 25.4 s
aggkit_test_timeout([==[cli: run --help lists every engine with options whose defaults the scene reader accepts and the engine uses]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[cli: the shipped constant-kernel scene passes against the exact solution]==] 80)  # measured 14.7 s
aggkit_test_timeout([==[clouds: a placement asked again is RSA's own, and a changed box, region, radius or seed places anew]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clouds: no overlaps, fresh per realization, velocities on their own stream]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cluster-level engine reproduces a brute-force oracle merge by merge]==] 30)  # measured 0.5 s
aggkit_test_timeout([==[clusters: a chain wrapped through the periodic corner is unwrapped into a straight chain]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: agree with an O(N^2) union-find on a random periodic gas]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: contacts across a periodic boundary join clusters (minimum image)]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: kinetic energy and bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: labels by first appearance, contacts inclusive of the contact distance]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: the size distribution is a distribution over clusters]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: union-find joins sets and counts components]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[clusters: unwrapping members that are not one cluster is an error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[collision observables: ED's hard-sphere gas against Carnahan–Starling, Henderson and Enskog]==] 40)  # measured 7.9 s
aggkit_test_timeout([==[collision observables: a head-on collision of hard spheres (ED) gives its impulse exactly]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[collision observables: a head-on collision of soft spheres (DEM) against the closed form]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[collision observables: an ideal gas has Z = 1 and P = Σ m|v|²/(d V)]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[collision observables: bad input is refused naming the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[concurrent SNES solves each read only their own PETSc options]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[constant kernel matches n_k = 4/(t+2)^2 (t/(t+2))^{k-1}]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[constant kernel with shattering follows the closed M0 equation]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[contacts of final aggregates: one contact per merge, few near contacts]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[continuation in lambda and in a reuses the previous solution]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[continuation in lambda reaches the root a direct solve finds]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[continuation on a coarse graded grid: the direct solve's root, then where the roots go negative]==] 30)  # measured 1.6 s
aggkit_test_timeout([==[cross approximation recovers an exactly rank-2 indefinite kernel]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a burst narrower than the outputs settles on its period and its troughs]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a missed crossing counts as two periods, a shrinking amplitude is not unsettled]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a modulation that decays is settling, never unsettled]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a periodic pulse train settles on its period]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a persisting modulation whose last three periods agree by chance is still unsettled]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a quasi-periodic modulation that persists is unsettled, with its mean period]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: a slow modulation is never settled from four periods, though three agree]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: at unequally spaced samples the peaks come from the parabola through them]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[crossing periods: too few crossings, and series of different lengths]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cycle branch and normal form: bad input is refused with the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cycle branch: continued from the Hopf point, the period of a long time series to 1e-3]==] 60)  # measured 11.1 s
aggkit_test_timeout([==[cycle extrapolation: bad options and starts are refused with the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[cycle extrapolation: next to the Hopf point RRE reaches the shot cycle in a few rounds]==] 30)  # measured 3.8 s
aggkit_test_timeout([==[dem: a binary head-on collision returns the calibrated restitution]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: a cloud with friction collapses, the Coulomb limit holds, the snapshot has angular velocities]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[dem: a cold cloud collapses to one aggregate, final.json follows the contract]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: a cold uniform sphere aggregates at the pressureless collapse time]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[dem: a compact overdamped cluster stays stable at dt = t_c/50 with the implicit dashpot]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: a frictional gas gives the same bits on 1 and 3 force threads]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[dem: a step above t_c/20 runs with a warning, the aggregation threshold is an option]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: a step beyond t_c/20 is warned about through the observer: summary.json and the terminal]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: adhesive fraction counts the contacts that never separate again]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: an elastic run reports a small energy drift]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: an elastic self-gravitating cloud keeps its energy]==] 30)  # measured 0.5 s
aggkit_test_timeout([==[dem: an overdamped collision at dt = t_c/50 sticks with the implicit dashpot, rebounds with the explicit one]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: an overdamped contact keeps the default step t_c/50 (implicit dashpot) unless friction makes it explicit]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: bad input is refused naming the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: elastic gases in periodic and reflecting boxes keep energy and momentum]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: fractal_dimension_com recovers known dimensions]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: fractal_dimension_com_all fits every sphere out to the farthest]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: impulse-split gravity costs little energy]==] 30)  # measured 0.5 s
aggkit_test_timeout([==[dem: oblique collisions with friction never gain energy, |F_t| <= μ F_n, angular momentum kept]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: observables at multiples of the free-fall time land at k t_ff, and at T_agg for runs that go on]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[dem: results do not depend on the gravity thread count, momentum kept to round-off]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[dem: the closed-form clipped collision]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: the contact lasts t_c]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: the dashpot scheme is an option, an explicit dashpot beyond x = 1 or t_c/20 is warned in the summary]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: the explicit dashpot returns the clipped restitution below x = 1, warned beyond]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: the implicit dashpot gives the same results for any thread counts]==] 30)  # measured 0.6 s
aggkit_test_timeout([==[dem: the implicit dashpot is stable and dissipative up to damping ratio 10^4 at dt = t_c/50]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[dem: the implicit dashpot relaxes a pure dashpot's relative velocity by exactly e^-x per step]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: the implicit dashpot returns the calibrated restitution]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: the same seed gives the same results for any thread counts]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[dem: the snapshot of a frictionless polydisperse cloud has each particle's radius and no angular velocity]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[dem: the tiled, vectorised direct sum against a plain loop, the same bits on any thread count]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: tree forces do not depend on the thread count]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: tree gravity collapses the cloud as the direct sum does]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[dem: tree gravity error falls with the opening angle]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dem: two bodies under direct gravity follow a Kepler orbit]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dem: without friction nothing rotates and oblique collisions keep the tangential velocity]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[draws are reproducible from the seed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: Fenwick selection returns the size holding a given rank]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: a bin picks its bucketed particles in increasing size by rank, through adds, removals and doubling]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: a binned population picks, removes and doubles particles of both kinds]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: a halving keeps floor or ceil of half of every size, and half the mass up to the odd ones]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: a population with every pair beyond the cutoff is frozen]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: a saved state with a damaged length anywhere is refused with a CheckpointError]==] 50)  # measured 8.2 s
aggkit_test_timeout([==[dsmc: bad engine options in a scene name the scene key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: bad options and models are refused with the key named]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: ballistic kernel, lambda = 0.01: M0, M2, M3 agree with CVODE within a few standard errors]==] 50)  # measured 9.2 s
aggkit_test_timeout([==[dsmc: constant kernel moments agree with the exact solution within a few standard errors]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dsmc: mass is conserved exactly through shattering and cloning]==] 30)  # measured 1.6 s
aggkit_test_timeout([==[dsmc: one cluster left is reported as extinction, not looped on]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: run seeds are the successive SplitMix64 outputs of the master seed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: runs reproduce the recorded trajectories bit for bit]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[dsmc: runs through several halvings follow the exact total density of K = 1 with shattering]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dsmc: size bins tile the sizes with hi/lo < 1.5]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: the corner bound of every bin pair bounds the kernel inside it]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dsmc: the drop truncation counts the mass it removes]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[dsmc: the error shrinks like N^-1/2 when the particle count grows 16x]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dsmc: the kernel table equals the kernel bit for bit, cutoff included, inside and beyond the table]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[dsmc: the same seed gives the same series bit for bit, threads or not, other seeds differ]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[dsmc: without population_halving the shattering population only grows]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed event queue: pops in time order, purges of stale events change no live event's turn]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ed: [compare] final tolerances compare final.json means with their standard errors]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: [particles] forms the engine cannot use are refused naming the key, the others run]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: a rerun into the same folder leaves no file the new scene does not write]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: bad [particles], stop and observe input name the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: extreme but valid scales finish, scales doubles cannot resolve are refused]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: no merge before the lattice gaps can close, then the pairs' own collision rate]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[ed: observables a kinetic engine cannot give are refused for it, naming the observable]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: outputs are unchanged from the recorded ones, file for file]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: realizations on threads give the same outputs as one after the other]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: series and final.json follow the contract and the physics]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ed: size distribution (PDF and CDF) at a chosen time]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ed: snapshots write final.vtu]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[ed: the shipped scene against the Smoluchowski equation with the 2-D ballistic kernel passes]==] 40)  # measured 7.6 s
aggkit_test_timeout([==[ed: the wall-time budget stops a run that would take too long, as a failed engine]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[ed: thermalize runs the elastic stage first, then sticking from t = 0]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ed: without stop the run ends at time.end, { clusters = K } stops at K]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[elastic gas follows the trajectory of the ED engine in elastic mode]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[elastic gas: a crowded cell grows the cell table]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[elastic gas: bad input is named]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[elastic gas: every event leaves no overlap and conserves energy and momentum]==] 70)  # measured 12.5 s
aggkit_test_timeout([==[elastic gas: head-on and oblique collisions by hand]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[elastic gas: particles keep their identity through the re-sorting]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[elastic gas: the clock renormalisation is invisible in long runs]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[elastic gas: thermalisation gives every particle its collisions]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[elastic mode conserves kinetic energy and momentum to round-off]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[engine dsmc: population_halving is a scene key, and off a growing population is never halved]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[engine dsmc: the wall-time budget stops a long ensemble as a failed engine]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[engine snes: bad options name the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[engine snes: petsc_options reach SNES, bad ones are refused before the run]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[engine snes: the shipped steady-state scene passes and writes the distribution]==] 30)  # measured 1.2 s
aggkit_test_timeout([==[every integrator reproduces the constant-kernel solution]==] 60)  # measured 10.3 s
aggkit_test_timeout([==[every preconditioner gives the same solution]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[exact moments: closed forms agree with the series]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[exact separable forms reproduce every kernel entry]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fast rates equal the direct oracle for every kernel]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[first_overlap finds the first overlapping pair, minimum image included]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fixed speeds have that speed, uniform components have zero momentum]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fixed-pivot shares keep number and mass of every aggregate]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension of the final aggregate grows with the volume fraction]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[fractal dimension: a gas filling its box has no fractal range]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: an aggregate wrapped through a periodic box is measured after unwrapping]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: box counting falls back to the published range for a box-filling set]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: box counting is exact on sets aligned with the dyadic grid]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: box counting on sets not aligned with the grid]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: degenerate input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[fractal dimension: mass-radius on a filled lattice and on Sierpinski triangles]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[fractal dimension: the published-range fallback on a box-filling gas]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[graded densities converge to the exact ones as r - 1 falls (constant kernel, t = 20)]==] 30)  # measured 1.2 s
aggkit_test_timeout([==[graded grid against exact solutions: M0 exact, M2 exact (three-, four-moment), M3 exact (four-moment) or second order]==] 30)  # measured 3.9 s
aggkit_test_timeout([==[graded grid keeps the a = 0.95, λ = 0.01 limit cycle of the uniform grid]==] 120)  # measured 22.4 s
aggkit_test_timeout([==[graded grid λ_crit against the converged uniform values]==] 30)  # measured 4.3 s
aggkit_test_timeout([==[graded pivots: K resolved sizes, then geometric sections up to N]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[graded rates conserve mass to round-off, and drop loses exactly the leak]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[graded rates with r = 1 are the discrete equations (against the direct O(N^2) rates)]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[hard-sphere gas: ideal limit and the virial relation between Z and the contact value]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[hard-sphere gas: the low-density virial coefficients]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: NaN, missing tolerances and failed engines in a comparison]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: a failing engine is recorded, the others still run, and the run fails]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: a folder holding only the write probe of a killed run is taken as new, the probe removed]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: a non-empty folder aggkit did not write is refused unless forced]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: a rerun removes what the previous run wrote, engines it no longer has included]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: a standard-error tolerance allows k combined standard errors at each time]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: a tolerance no solver can meet fails with exit code 1]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: an atomic file exists under its name only after commit]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: an output folder under a regular file is refused before anything runs]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: bad input found while running stops the run without a summary]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: committing a file nobody wrote is an error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: comparison takes the largest relative error over the output times]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: constant kernel against the exact solution writes every output and passes]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: final values against stated values, with and without a reference engine]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: progress names the engine and the time reached, and is silent when quiet]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: series measures are taken per realization and compared as final values of any engine]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: size distributions are compared by their Euclidean distance against standard errors]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[harness: stale outputs of an earlier run are removed before a run starts]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[harness: the shipped DSMC scene passes with ar, fast and cvode agreeing]==] 40)  # measured 7.7 s
aggkit_test_timeout([==[head-on approach: gap over closing speed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[hopf_curve bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[hopf_curve reproduces the N = 8192 lambda_crit within its error bars]==] 150)  # measured 29.3 s
aggkit_test_timeout([==[job slots: a child on several slots runs its spread command line with its environment]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[job slots: a spreading job takes what is free, at most what it can use]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[job slots: over random runs no slot is lost, none is double-booked and none idles while a job waits]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[job slots: the scan starts first on every free slot, then the full tier, then the fast, one slot each]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[kernel values follow their formulas]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[lambda_crit converges geometrically in N (a = 1)]==] 110)  # measured 20.4 s
aggkit_test_timeout([==[lattice sites fill the box without overlap]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[least squares: degenerate input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[least squares: slope, intercept and standard errors of a hand-computed case]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[least squares: the standard error matches the scatter of slopes over noisy replicas]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[limit cycle: Newton converges fast from a start near a relaxation-type cycle, far below the curve]==] 160)  # measured 30.6 s
aggkit_test_timeout([==[limit cycle: bad options and starts are refused with the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[limit cycles by shooting: the period of a long time series to 1e-3, a periodic orbit, stable multipliers]==] 240)  # measured 20.0 s
aggkit_test_timeout([==[locate_hopf brackets λ_crit(a) and reports ω]==] 90)  # measured 17.4 s
aggkit_test_timeout([==[locate_hopf from a start at another (a, λ) follows its branch to the same lambda_crit]==] 30)  # measured 2.3 s
aggkit_test_timeout([==[locate_hopf reports a missing steady state at lambda_lo instead of failing]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[locate_hopf steps a bracket that misses the crossing]==] 90)  # measured 17.6 s
aggkit_test_timeout([==[locate_hopf steps up from a bracket with no positive steady state]==] 30)  # measured 4.6 s
aggkit_test_timeout([==[logistic fit: exact data give back the four parameters]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[logistic fit: the midpoint's standard error is calibrated on noisy data]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[logistic fit: too few or non-finite points give no fit, mismatched lengths are bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[low-rank approximation never forms the matrix and still holds at large N]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[low-rank factors meet the steady state's tolerance 1e-12 at large N]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[mass is conserved to 1e-12 under cutoff with shattering]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[max_steps stops a run with a clear error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[merges relabel the absorbed cluster and keep every member]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[minimum image and wrap along periodic axes only]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[negative_mass_fraction weighs each entry by its size]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[neighbour grid: a sparse set does not allocate a cell per cutoff length]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[neighbour grid: same pairs as the O(N^2) search]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[neighbours wrap across periodic faces and stop at walls]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[no cancellation for a nearly tangent fast pair]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[normal, lognormal and uniform radii have the analytic mean and sd]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oblique approach: smallest root of the quadratic]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oblique contact: merged cluster moves with the mean velocity]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[observables: evaluated on a density state]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[observables: evaluated on a particle state, computing only what is asked]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[observables: names M<p>, n<k> and the plain names of the registry]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[observables: needs say what a state must give]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[observables: oscillation measures of a series against sines whose measures are known exactly]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[on_step sees every internal step's densities, which follow the exact solution]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[open space: a sphere cloud of a given volume fraction around the origin]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[option rows: a sub-table's keys, types and required keys are checked]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[option rows: a value just outside each printed bound is refused, one just inside accepted]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[option rows: the library's own validate() is the rows' range check]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[option rows: the printed default is the value a run uses, and giving it changes nothing]==] 30)  # measured 0.7 s
aggkit_test_timeout([==[option rows: validate() refuses exactly what the rows' ranges refuse, at each bound]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: a damped sine is damped with its decay rate]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: a decay slower than the drift tolerance over the tail counts as sustained]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: a pure sine is sustained with its period and amplitude]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: a slowly growing oscillation is sustained but not converged]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: bad series and criteria are rejected]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: noise]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: relaxation to a constant is damped (monotone) or steady once relaxed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[oscillation: too few cycles in the tail give a tentative verdict]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[overlap by round-off while approaching collides at once]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[overlap windows agree with a direct scan]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[overlap windows: a bounded search returns the same window or a recheck no later than it]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[overlap windows: hand cases]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[particle snapshot: a plotter that fails gives a message, not an exception or a file]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[particle snapshot: per-particle radii and angular velocities survive the binary form bit for bit]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[particle snapshot: sizes that do not match the particles are an input error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[particle snapshot: the binary .vtu decodes to every value written, one vertex per particle]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[particle snapshot: the cluster picture is a PNG]==] 70)  # measured 12.1 s
aggkit_test_timeout([==[particles: a start file relative to the scene file's folder]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[particles: bad input through the CLI exits 2 naming the key and value]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[particles: bad start files name the file and the line]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[particles: bad values name the full key and show the value]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[particles: radius and mass laws, clouds and open space parse]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[particles: today's lattice form keeps its box and start]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[periodic boundary: contact across the box face]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[polydisperse: a chain of unequal spheres across a periodic wall is unwrapped through its contacts]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[polydisperse: contact clusters and relative contacts match every pair checked by brute force]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[polydisperse: one radius for every particle, given per particle, is the equal-radius case]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[product kernel matches M2 = 1/(1-t) before gelation]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[progress callbacks of a long advance see the clock run and the clusters fall]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[rank share: a failure on one rank fails the share on every rank, rank 0 naming the rank]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[rank share: rank k runs k, k + K, ..., rank 0 gets every result in realization order, idle ranks]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[receding, missing and grazing pairs]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[reflecting wall reverses a particle and the wall takes 2 m v]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[return map: bad options and references are refused with the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[return map: the estimate from the deviations, and where the noise next to the floor allows only a bound]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[return map: the largest Floquet multiplier agrees with Arnoldi's on the shot cycle]==] 300)  # measured 58.2 s
aggkit_test_timeout([==[run cli: mpirun -np 2 spreads the ED realizations and writes the files of one process]==] 50)  # measured 8.9 s
aggkit_test_timeout([==[run cli: mpirun spreads the DSMC runs, with idle ranks when there are more ranks than runs]==] 40)  # measured 6.1 s
aggkit_test_timeout([==[run cli: under mpirun a bad scene ends every rank with exit 2, and checkpoints are refused]==] 50)  # measured 8.1 s
aggkit_test_timeout([==[run cli: under mpirun the deterministic engines (snes, cvode) run on rank 0 alone]==] 30)  # measured 1.8 s
aggkit_test_timeout([==[run records: a JSON record is one whole object, anything else is no record]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[run records: a damaged, truncated or foreign file is not a record]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[run records: a number field is the whole field read as a number]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[run records: one row under the exact header is a record, with its fields]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan cli: a column that stops decides nothing and the points below say where and why]==] 30)  # measured 2.3 s
aggkit_test_timeout([==[scan cli: a relaxing point that does not relax on the refined grid is unresolved]==] 30)  # measured 2.3 s
aggkit_test_timeout([==[scan cli: a run budget too short to reach the cycle leaves the point unstable and says why]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[scan cli: a scan killed while running continues from its finished points]==] 150)  # measured 28.3 s
aggkit_test_timeout([==[scan cli: an interrupted scan resumes without recomputing its finished points]==] 100)  # measured 18.7 s
aggkit_test_timeout([==[scan cli: bad input exits 2 naming the key and the value]==] 80)  # measured 15.6 s
aggkit_test_timeout([==[scan cli: far below the curve the column resolves the quiescent phase of the relaxation cycles]==] 30)  # measured 3.2 s
aggkit_test_timeout([==[scan cli: one process and mpirun -np 2 write the same scan.csv and lambda_crit.csv]==] 50)  # measured 9.5 s
aggkit_test_timeout([==[scan cli: the columns are walked first, and a point its column reached seeks no cycle of its own]==] 30)  # measured 1.1 s
aggkit_test_timeout([==[scan cli: the converged Hopf curve runs beside the columns, with the same results on 2 ranks]==] 30)  # measured 2.8 s
aggkit_test_timeout([==[scan cli: the cycle continued down a column decides the points whose own search cannot reach it]==] 30)  # measured 4.8 s
aggkit_test_timeout([==[scan cli: the truncation check repeats points and the lambda_crit bracket at 2N]==] 40)  # measured 7.3 s
aggkit_test_timeout([==[scan cli: where the grid's roots go negative the steady state is sought on the refined grid]==] 30)  # measured 4.9 s
aggkit_test_timeout([==[scan columns: a stable focus beside the column's settled cycle is bistable, with the cycle's figures]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan columns: an unsettled column step makes no point bistable, and a sustained point takes the multiplier]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan lambda_crit: no bracket on the grid, and non-monotone grids, are reported]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan lambda_crit: the bracket's midpoint, arithmetic or geometric, with the half width as error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan plan: a missing or malformed file is bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan plan: bad input names the key and the value]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan plan: lists, linear and log ranges]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan plan: the point model carries a, lambda and N, the fingerprint ignores the grid]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan point: a = 0.9, lambda = 0.01 is damped towards the steady state]==] 110)  # measured 20.8 s
aggkit_test_timeout([==[scan point: a = 0.95, lambda = 0.01 is sustained with the long run's swing and period]==] 290)  # measured 58.0 s
aggkit_test_timeout([==[scan point: a cycle search beyond cycle_steps stops and says so, and a bad cycle_steps is refused]==] 30)  # measured 0.6 s
aggkit_test_timeout([==[scan point: a relaxation that ends far from its steady state is unresolved, not damped]==] 30)  # measured 3.8 s
aggkit_test_timeout([==[scan point: a relaxation without a steady state to confirm it is unresolved, not damped]==] 30)  # measured 1.3 s
aggkit_test_timeout([==[scan point: confirm_run without stability is refused with the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan point: the progress line's outcome names only the numbers the regime has]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scan point: where the growth off the steady state is beyond cycle_run, the search starts on the Hopf normal form's cycle]==] 30)  # measured 1.2 s
aggkit_test_timeout([==[scan point: with confirm_run the run's length comes from the spectrum, and a long one is not run]==] 30)  # measured 1.2 s
aggkit_test_timeout([==[scene: a grid given by `every` ends exactly at the end and matches distribution times]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: a missing, unreadable or malformed scene file is an InputError naming the path]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: compare.final values against stated values need no reference, other forms still do]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: each bad input is an InputError naming its key and value]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: every shipped scene parses]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: kernel parameters, the forms of lambda(t), cutoff and a tabulated start]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: the README example parses to the ballistic model with shattering]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: the fixture scene parses to its model, grid, engines and comparison]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: the kernel registry is what the parser accepts and what its messages list]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: the tier is fast unless the scene says full]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: the tolerance table form is read and checked]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[scene: unknown keys are named with the keys that are allowed]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[section_densities gives back the density whose sizes the numbers count]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[shape: N_c of a cubic lattice and of a periodic square lattice]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shape: N_c of a full hexagonal patch matches the count of its nearest-neighbour bonds]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shape: gyration in 3-D of six points on rotated axes]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shape: gyration of an ellipse-shaped set has eigenvalues a²/4, b²/4 and its orientation]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shape: gyration of random points filling an ellipse, within the sampling error]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shape: pair distribution agrees with an O(N^2) count on a random 3-D set]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[shape: pair distribution of four particles counted by hand]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[shattering drives M0 to the steady state 2λ/(1+2λ)]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[shattering rate laws and their validation]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[stability bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[steady-state bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sum kernel matches M0 = e^{-t}, M2 = e^{2t}]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[sweep cli: a key that is not a scene key is exit 2 naming it, with no outputs]==] 60)  # measured 11.5 s
aggkit_test_timeout([==[sweep cli: an interrupted sweep resumes without rerunning its finished runs, heat maps]==] 110)  # measured 21.7 s
aggkit_test_timeout([==[sweep cli: means pooled over swept keys equal a direct computation over sweep.csv, F := 0 where T_agg is undefined]==] 30)  # measured 4.8 s
aggkit_test_timeout([==[sweep cli: realizations differ, and sweep_mean.csv holds their means and standard errors]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[sweep cli: the product of the keys, one row per run with its final values, and the same CSV under mpirun -np 2]==] 50)  # measured 8.5 s
aggkit_test_timeout([==[sweep plan: a key the scene does not have, or a value it refuses, is an error naming the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep plan: engines are named as the only one, by index or by label]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep plan: group_by pools over the other keys, where_not_aggregated sets columns of runs that never aggregated]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep plan: realization r raises every seed by r, an integer key gets integers from a range]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep plan: the product of the keys, the first written slowest, each point's scene]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep plan: the shipped campaign is the published 245 runs over γ_n and k̃_n, and runs its base point]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep records: point, realization and rank are read from JSON integers only, and a float in them is no record]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[sweep tables: sweep.csv rows and sweep_mean.csv means and standard errors over the finite values]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[the Jacobian-vector product is the derivative of the right-hand side]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[the coarse-to-fine start finds the steady state of the direct solve]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[the engine, its elastic gas and cell grids refuse an open boundary]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[the growth rate of a perturbation under CVODE is Re of the rightmost pair]==] 30)  # measured 1.1 s
aggkit_test_timeout([==[the lattice start with a fixed radius is today's start bit for bit]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[the low-rank kernel's default tolerance is 10 rtol, and the run still meets rtol]==] 30)  # measured 3.2 s
aggkit_test_timeout([==[the preconditioner keeps GMRES iterations low]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[the real stability boundary of Dormand-Prince 5(4) is the published 3.31]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[the right-hand side conserves mass up to the leak]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[the trivial mass mode is excluded]==] 30)  # measured 0.6 s
aggkit_test_timeout([==[thermalisation: every particle collides enough, then the clock restarts and sticking is on]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[three particles: the pair merges first, then the third joins]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[three- and four-moment shares keep number, mass, x² (and x³) of every aggregate]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[tournament tree: top and subtree winners agree with a scan]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[trajectory scene: frames at the output times at least `every` apart]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[trajectory scene: the file count and the disk estimate are bounded before the run]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ts: 2-D periodic run to one cluster]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[ts: 2-D reflecting run to one cluster]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ts: 3-D reflecting and periodic runs to one cluster]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ts: a contact-time merge that stops a disc on a third one links the third in the same flight]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: a start with overlaps is refused naming particles.initial]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: a step of many diameters misses no contact (substeps), as ED]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: as dt -> 0 the merge order, times and final offsets converge to ED's]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: bad options and [particles] name the key]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: contact detection split over two threads gives the same run as one]==] 30)  # measured 0.8 s
aggkit_test_timeout([==[ts: contact-time merges spread over two threads give the same run as one, to one cluster]==] 30)  # measured 0.3 s
aggkit_test_timeout([==[ts: local detection (only the spheres whose safe time ran out examined) gives the same run as examining every sphere, on one and two threads]==] 30)  # measured 1.1 s
aggkit_test_timeout([==[ts: physics against ED [Degond2024, Sec. 4.2]: D_f, N_c and P(r) over 10 realizations]==] 40)  # measured 7.6 s
aggkit_test_timeout([==[ts: quiet flights (detection skipped within a safe time) give the same run as detecting every flight]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ts: quiet flights are logged and replayed: wall bounces, reads and checkpoints in a quiet stretch change nothing]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: re-checking only the spheres that can meet another cluster after contact-time merges gives the same run]==] 30)  # measured 1.0 s
aggkit_test_timeout([==[ts: runs with every contact resolved by the minimisation (contact_time off), 2-D and 3-D]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[ts: series and final.json follow the contract]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: the shipped TS-vs-ED scenes (2-D and 3-D) pass and the final aggregates agree]==] 30)  # measured 0.4 s
aggkit_test_timeout([==[ts: two cluster threads give the same run as one]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[ts: two discs in a head-on collision merge once, momentum conserved, touching]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[two particles head-on merge at rest]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[under drop the leaked mass equals the loss of M1]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[uniform components have zero momentum with unequal masses, speed 0 is a cold start]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[up to N = 256 the reported low-rank error is the error on all entries]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[validate cli: --jobs 2 runs a scan scene first on both cores as MPI ranks, with the outputs of --jobs 1]==] 30)  # measured 2.4 s
aggkit_test_timeout([==[validate cli: a passing and a failing scene give exit 1, the table, validation.json and report.html]==] 240)  # measured 46.6 s
aggkit_test_timeout([==[validate cli: a validation killed midway continues without rerunning its finished scenes]==] 180)  # measured 36.0 s
aggkit_test_timeout([==[validate cli: bad input is exit 2, naming the option, the value and what is allowed, before anything runs]==] 30)  # measured 0.9 s
aggkit_test_timeout([==[validate cli: exit 0 when every scene passes, and a scene file named explicitly runs whatever its tier]==] 30)  # measured 2.2 s
aggkit_test_timeout([==[validate: a finished record is read back, and a damaged one is no record]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[validate: text on the page is escaped and image paths are URLs]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[validate: the description is the scene file's opening comment]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[validate: the plan reads every scene first, tiers, names and bad input]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[validate: the worst comparison is a failed one, else the one using most of its tolerance]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[worker pool: a throwing job is rethrown after the others finished, and the pool stays usable]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[worker pool: a worker late for a claimed run does not run the next run_each's job twice]==] 30)  # measured 1.9 s
aggkit_test_timeout([==[worker pool: destroyed with blocked workers]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[worker pool: each job runs once, polling or blocked workers]==] 190)  # measured 37.6 s
aggkit_test_timeout([==[worker pool: jobs run on several threads and write their own outputs]==] 30)  # measured 0.1 s
aggkit_test_timeout([==[worker pool: run_each runs job t on thread t, the caller's job 0, the same thread every run]==] 30)  # measured 0.2 s
aggkit_test_timeout([==[zero-momentum start keeps zero momentum]==] 30)  # measured 0.1 s
