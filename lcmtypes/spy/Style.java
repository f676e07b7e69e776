package lasonic.spy;

import java.awt.Color;

/** Colours shared by the lasonic lcm-spy plugins; the same as lasonic-render's Fig. 8 panels. */
public final class Style {
  private Style() {}

  public static final Color LASER = new Color(31, 94, 191);          // laser, Radar Map lines
  public static final Color SONAR = new Color(237, 120, 0);          // sonar (complementary)
  public static final Color SONAR_COPIED = new Color(250, 191, 115); // sonar value copied to a neighbour
  public static final Color SONAR_LINE = new Color(217, 84, 0);      // lines from the tactical AGM
  public static final Color AGM_WEIGHT = new Color(250, 158, 64);    // AGM cell with G > 0
  public static final Color AGM_OCCUPIED = new Color(140, 56, 0);    // AGM cell with Gp >= threshold
  public static final Color AGM_UNCHECKED = new Color(120, 110, 160); // ... that only echoes the laser could not check made
  public static final Color ROBOT = new Color(26, 26, 26);
  public static final Color GRID = new Color(235, 235, 235);
  public static final Color NOTE = new Color(115, 115, 115);
  public static final Color STALE = new Color(214, 26, 26);
  public static final Color TEXT = new Color(26, 26, 26);
  public static final Color UNKNOWN = new Color(200, 0, 200);        // a source value we do not know

  /** [m] MOBOT-IV's radius (the scenarios' default): grid and line maps do not carry the robot's. */
  public static final double ROBOT_RADIUS = 0.35;

  /** c with the given alpha (0..255). */
  public static Color alpha(Color c, int a) {
    return new Color(c.getRed(), c.getGreen(), c.getBlue(), Math.max(0, Math.min(255, a)));
  }
}
