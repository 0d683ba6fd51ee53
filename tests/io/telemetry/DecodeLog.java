// Reads an LCM log file and decodes every event with the generated Java class of its channel
// (codesign_lcm_types.jar, the jar lcm-spy uses). A class's constructor from a DataInput checks
// the fingerprint, so a message that the jar's types cannot read counts as a failure.
//
// Prints one line "<channel> <messages decoded> <sum of their timestep fields>" per channel seen
// (sorted by name), then "failures <n>" (undecodable events or unknown channels). Exit status 0
// when n is 0, 1 otherwise, 2 when the log cannot be read.
//
//   java -cp /usr/share/java/lcm.jar:codesign_lcm_types.jar:<dir of DecodeLog.class> DecodeLog log.lcm
import java.io.EOFException;
import java.io.IOException;
import java.util.Map;
import java.util.TreeMap;

public class DecodeLog {
  private static long decode(String channel, byte[] data) throws IOException {
    switch (channel) {
      case "CODESIGN_SIM_STEP": return new codesign_lcm.sim_step_t(data).timestep;
      case "CODESIGN_TRAIN_STEP": return new codesign_lcm.sim_step_t(data).timestep;
      case "CODESIGN_EPISODE": return new codesign_lcm.episode_t(data).timestep;
      case "CODESIGN_PPO": return new codesign_lcm.ppo_update_t(data).timestep;
      case "CODESIGN_DISTRIBUTION": return new codesign_lcm.distribution_t(data).timestep;
      case "CODESIGN_POLICY_MEMORY": return new codesign_lcm.policy_memory_t(data).timestep;
      default: throw new IOException("unknown channel " + channel);
    }
  }

  public static void main(String[] args) {
    if (args.length != 1) {
      System.err.println("usage: DecodeLog <log.lcm>");
      System.exit(2);
    }
    Map<String, long[]> seen = new TreeMap<>();  // channel -> {count, timestep sum}
    int failures = 0;
    try {
      lcm.logging.Log log = new lcm.logging.Log(args[0], "r");
      while (true) {
        lcm.logging.Log.Event ev;
        try {
          ev = log.readNext();
        } catch (EOFException end) {
          break;
        }
        if (ev == null) break;
        try {
          long t = decode(ev.channel, ev.data);
          long[] s = seen.computeIfAbsent(ev.channel, k -> new long[2]);
          s[0] += 1;
          s[1] += t;
        } catch (IOException e) {
          System.err.println("DecodeLog: " + ev.channel + ": " + e.getMessage());
          failures++;
        }
      }
      log.close();
    } catch (IOException e) {
      System.err.println("DecodeLog: cannot read " + args[0] + ": " + e.getMessage());
      System.exit(2);
    }
    for (Map.Entry<String, long[]> e : seen.entrySet())
      System.out.println(e.getKey() + " " + e.getValue()[0] + " " + e.getValue()[1]);
    System.out.println("failures " + failures);
    System.exit(failures == 0 ? 0 : 1);
  }
}
