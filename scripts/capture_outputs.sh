#!/bin/bash
# capture_outputs.sh BIN OUTDIR: runs a fixed set of commands with the binary BIN and keeps
# their stdout, stderr and files in OUTDIR. Run it with the binaries of two commits and
# compare the directories with compare_outputs.py to show that a refactoring kept every
# output (timing fields differ from run to run and are masked by the comparison; the
# tour's stdout and index.html print timings inline and always differ).
B=$1; O=$2; rm -rf $O; mkdir -p $O; cd $O
run() { name=$1; shift; "$B" "$@" > $name.stdout 2> $name.stderr; echo "rc=$?" >> $name.stdout; }
run rot rotation --from axis-angle --values 1,2,3,0.7 --json
run rot_e rotation --from euler:3-1-3 --values 0.3,0.4,0.5 --json
run sph_hol sphere holonomy --theta 1.1 --phi1 0.3 --phi2 2.2 --json --out sph_hol
run sph_plan sphere plan --angle 2pi/3 --axis 1,1,1 --json --out sph_plan
run sph_eplan sphere euler-plan --set 3-2-3 --angles 0.3,0.5,0.7 --json --out sph_eplan
run sph_roll sphere roll --theta 1 --phi1 0.2 --phi2 2 --json --out sph_roll
run sph_rollc sphere roll --circle 0.5 --json
run sph_study sphere roll --theta 1 --phi1 0.2 --phi2 2 --study --json --out sph_study
run cyl_sup cylinder support --theta 30deg --json
run cyl_sup2 cylinder support --theta 1.2 --r-over-h 0.3 --mu 0.5 --json
run cyl_stat cylinder statics --out cyl_stat
run cyl_rect cylinder holonomy rectangle --theta 0.3 --phi1 13pi/3 --phi2 29pi/4 --json --out cyl_rect
run cyl_circ cylinder holonomy circle --ell 2 --theta 0.4 --h 1 --r 0.3 --json --out cyl_circ
for s in single pair7 pair9; do for c in generic touching; do run cyl_frob_${s}_$c cylinder frobenius --system $s --config $c --json; done; done
run nsga_ball nsga ball --case 2 --json --out nsga_ball
run nsga_ball3 nsga ball --case 3 --scheme moreau --json
run nsga_wp nsga work-precision --system oscillator --dts 4e-3,2e-3 --json --out nsga_wp
run lire blocks lire --json --out lire
run lire_top blocks lire --perturb top --t-end 3 --json --out lire_top
run lire_floor blocks lire --floor --json --out lire_floor
run sw_freq blocks sweep frequency --omega 2:6:1 --json --out sw_freq
run sw_slide blocks sweep slide --v0 0.5:2:0.5 --json --out sw_slide
run painleve blocks painleve --aspect 0.5 --mu 0.6 --json --out painleve
run tour tour --out tour
run run_shake blocks run shaking --t-end 1.5 --json --out run_shake
run run_slide blocks run slide --t-end 1 --json --out run_slide
